#pragma once
// The profile's "atmosphere" section: LUT sizes, sample counts, per-LUT update
// schedules, invalidation thresholds and the space fallback. Defaults are the
// desktop values (Hillaire 2020 reference sizes, the seed's update periods).
#include <array>
#include <string>

#include <nlohmann/json.hpp>

namespace cr {

enum class LutKind { Transmittance = 0, MultiScattering = 1, SkyView = 2, AerialPerspective = 3 };
inline constexpr int kLutKinds = 4;
const char* lut_name(LutKind kind);  // "transmittance", "multiscattering", "skyview", "aerial_perspective"

struct LutSchedule {
  int period = 1;  // frames between the starts of two periodic refreshes
  int slices = 1;  // frames one rebuild is spread over (1 = whole LUT in one frame)
};

// Arithmetic of the LUTs' consumers ("precision" section): float32 LUTs and
// a float composite (desktop), or LUTs quantised to 15-bit fixed point after
// each (float) bake and, optionally, sampled and composited per pixel in
// 16-bit integer arithmetic (mobile).
enum class LutPrecision { Float32, Q15 };
enum class CompositePrecision { Float, Fixed };

struct AtmosphereSettings {
  int transmittance_width = 256;
  int transmittance_height = 64;
  int transmittance_steps = 40;

  int multiscattering_width = 64;   // sun zenith axis (Psi falls steeply into Earth's shadow)
  int multiscattering_height = 32;  // altitude axis
  // Orders above the second marched before the series: explicit_orders_for()
  // picks between these two by f_ms (tail_share 1: always the minimum).
  int multiscattering_explicit_orders = 0;
  int multiscattering_max_explicit_orders = 4;
  float multiscattering_tail_share = 0.15f;
  int multiscattering_directions = 64;  // n*n stratified directions, n even
  int multiscattering_steps = 20;
  float multiscattering_max_fms = 0.95f;  // clamp of the series ratio: 1/(1 - f_ms) <= 20

  int skyview_width = 192;
  int skyview_height = 108;
  int skyview_min_steps = 4;
  int skyview_max_steps = 14;

  int ap_width = 32;
  int ap_height = 32;
  int ap_depth = 32;
  float ap_km_per_slice = 4.0f;
  int ap_steps_per_slice = 2;

  std::array<LutSchedule, kLutKinds> schedule{{{16, 1}, {16, 1}, {4, 1}, {6, 1}}};
  bool full_schedule = false;  // rebuild all four LUTs (and the environment) every frame

  // The prefiltered specular environment (sky_environment.h): level 0's
  // octahedral width (a power of two), GGX levels, samples per texel of a
  // level of level 0's size, and its own schedule (invalidated by the
  // thresholds below like the sky-view LUT).
  int environment_size = 64;
  int environment_levels = 6;
  int environment_samples = 32;
  LutSchedule environment_schedule{16, 4};

  float invalidate_sun_deg = 0.5f;     // sun zenith/direction change that forces sky-view and AP rebuilds
  float invalidate_camera_m = 50.0f;   // camera move (altitude for sky-view, position for AP)
  float invalidate_camera_deg = 5.0f;  // camera rotation or fov change (AP)

  LutPrecision lut_precision = LutPrecision::Float32;
  CompositePrecision composite_precision = CompositePrecision::Float;

  // Wavelengths the LUTs are baked at: 3 = the RGB model (680/550/440 nm);
  // 6, 9, ... = that many bands over 380-780 nm, baked in groups of three
  // and mixed into RGB at publish (spectral_sampling.h, spectral_mix.h).
  int spectral_samples = 3;

  double space_altitude = 100e3;  // above this camera altitude: per-pixel ray marching, no sky-view/AP
  int space_steps = 24;           // steps of the per-pixel march (also used beyond the AP range)
};

// Throws InputError(file, "atmosphere.<field>: ...").
AtmosphereSettings parse_atmosphere_settings(const nlohmann::json& section, const std::string& file);

}  // namespace cr

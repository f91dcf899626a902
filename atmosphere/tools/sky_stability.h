#pragma once
// One cell of the sky's stability map: the LUT pipeline as the plugin runs it
// (all four LUTs rebuilt for one camera altitude and sun), its sky on a small
// panorama against the path-traced reference (optional: the tests skip it),
// non-finite values in every LUT and output, and which fallbacks engaged:
//  - the space fallback: above space_altitude the sky-view LUT is built for
//    the true altitude and geometry gets a per-pixel ray march;
//  - the multi-scattering series clamp: texels whose f_ms exceeded max_fms,
//    where the series 1 / (1 - f_ms) is capped;
//  - the explicit orders' cap: max_explicit_orders reached with the series'
//    share still above tail_share (explicit_orders_for);
//  - transmittance underflow: transmittance LUT texels at exactly 0 (the LUT
//    holds only rays that miss the ground, so a 0 is an optical depth past
//    float's range, not the planet's shadow).
#include <cstddef>
#include <cstdint>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/spectral_sampling.h"
#include "atmosphere/tools/accuracy_score.h"
#include "engine/core/job_system.h"

namespace cr {

struct SkyStabilityOptions {
  int width = 16, height = 8;  // the panorama (sky_panorama.h)
  bool reference = true;       // render the reference and score against it
  int spp = 512;               // the reference's paths per pixel
  uint64_t seed = 1;
  SpectralSampling sampling = rgb_sampling();  // the reference's wavelengths
};

struct SkyStabilityCell {
  AccuracyScore score;  // over the scored sky (sky_panorama.h); empty without the reference
  size_t non_finite_luts = 0;       // over every texel of every published LUT and the MS moments
  size_t non_finite_sky = 0;        // the panorama's sky radiance
  size_t non_finite_geometry = 0;   // aerial perspective (or the space march) of ground seen in the panorama
  size_t non_finite_reference = 0;  // the reference's radiance and noise
  bool space = false;
  size_t ms_texels = 0, ms_clamped = 0;  // multi-scattering texels, and those whose f_ms was clamped
  float max_fms = 0.0f;                  // largest unclamped f_ms in the LUT
  int explicit_orders = 0;
  bool orders_capped = false;  // in any wavelength group
  size_t transmittance_texels = 0, transmittance_underflow = 0;
  double lut_ms = 0.0, ref_ms = 0.0;
  size_t non_finite() const { return non_finite_luts + non_finite_sky + non_finite_geometry + non_finite_reference; }
};

// `altitude` above the ground (m; the ground itself at 0), sun `sun_zenith_deg` from the zenith.
SkyStabilityCell evaluate_sky_stability(const AtmosphereModel& model, const AtmosphereSettings& settings,
                                        double sun_zenith_deg, double altitude, const SkyStabilityOptions& options,
                                        JobSystem& jobs);

// The model with every constituent's density (Rayleigh, Mie, ozone) times `scale`.
AtmosphereModel with_density_scale(AtmosphereModel model, float scale);

}  // namespace cr

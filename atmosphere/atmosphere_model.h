#pragma once
// The physical atmosphere: a spherical planet with a Rayleigh layer, a Mie
// (aerosol) layer and an ozone layer, as in Hillaire 2020 / Bruneton 2017.
// Coefficients are per metre at the ground; densities are functions of the
// altitude above the ground sphere. Presets and scene-file parsing live here.
#include <cstdint>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cr {

enum class MiePhaseModel { CornetteShanks, DoubleHenyeyGreenstein };

struct AtmosphereModel {
  double bottom_radius = 6360e3;  // ground sphere (m)
  double top_radius = 6460e3;     // top of the atmosphere (m)

  glm::vec3 rayleigh_scattering{5.802e-6f, 13.558e-6f, 33.1e-6f};
  float rayleigh_scale_height = 8000.0f;

  // Extinction 4.44e-6 /m with single-scattering albedo 0.9 (Bruneton 2017's
  // reference implementation; Hillaire 2020's table prints the absorption as
  // 4.4e-6, ten times this, which would make the haze a tenth as bright).
  glm::vec3 mie_scattering{3.996e-6f};
  glm::vec3 mie_absorption{0.444e-6f};
  float mie_scale_height = 1200.0f;
  MiePhaseModel mie_phase = MiePhaseModel::CornetteShanks;
  float mie_g = 0.8f;            // Cornette-Shanks g, or the first HG lobe of the double HG
  float mie_g2 = -0.4f;          // second (backward) HG lobe
  float mie_lobe_weight = 0.9f;  // weight of the first HG lobe

  glm::vec3 ozone_absorption{0.650e-6f, 1.881e-6f, 0.085e-6f};
  float ozone_center = 25000.0f;      // altitude of the tent's peak (m)
  float ozone_half_width = 15000.0f;  // density falls to 0 at center +- half width (m)

  glm::vec3 ground_albedo{0.3f};
  float sun_angular_radius = 0.004675f;  // radians (0.2678 deg)

  double atmosphere_height() const { return top_radius - bottom_radius; }
  bool operator==(const AtmosphereModel&) const = default;
};

// Scattering and extinction of the medium at one altitude.
struct MediumSample {
  glm::vec3 rayleigh_scattering;
  glm::vec3 mie_scattering;
  glm::vec3 scattering;  // rayleigh + mie
  glm::vec3 extinction;  // scattering + mie and ozone absorption
};

// Relative densities of the three constituents (1 = ground level; ozone: tent peak).
struct Densities {
  float rayleigh;
  float mie;
  float ozone;
};

// The density profile with its divisions precomputed, for inner loops.
struct DensityProfile {
  float inv_rayleigh_height;
  float inv_mie_height;
  float ozone_center;
  float inv_ozone_half_width;

  explicit DensityProfile(const AtmosphereModel& m)
      : inv_rayleigh_height(1.0f / m.rayleigh_scale_height),
        inv_mie_height(1.0f / m.mie_scale_height),
        ozone_center(m.ozone_center),
        inv_ozone_half_width(1.0f / m.ozone_half_width) {}
  Densities at(float altitude) const;  // defined in atmosphere_density.h (inline)
};
MediumSample sample_medium(const AtmosphereModel& m, float altitude);

// Named presets: earth-clear, earth-hazy, earth-thin, earth-dense, mars-like.
// Throws std::out_of_range for an unknown name.
AtmosphereModel atmosphere_preset(const std::string& name);
const char* const* atmosphere_preset_names();  // null-terminated

// Checks physical validity; returns an empty string when valid, else what is
// wrong naming the field ("mie_g: |g| must be < 1").
std::string validate_atmosphere(const AtmosphereModel& m);

// The scene file's "atmosphere" section.
struct AtmosphereSceneConfig {
  AtmosphereModel model;
  std::string preset = "earth-clear";
  double ground_altitude = 0.0;  // altitude (m) of world y = 0 above the ground sphere
};
// Throws InputError(file, "atmosphere.<field>: ...") on unknown keys or bad values.
AtmosphereSceneConfig parse_atmosphere_scene(const nlohmann::json& section, const std::string& file);

}  // namespace cr

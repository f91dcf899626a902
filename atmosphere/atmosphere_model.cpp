#include "atmosphere/atmosphere_model.h"

#include <cmath>
#include <stdexcept>

#include "atmosphere/atmosphere_density.h"
#include "atmosphere/config_fields.h"
#include "atmosphere/reference_atmosphere.h"
#include "engine/core/error.h"
#include "engine/core/math_constants.h"

namespace cr {

MediumSample sample_medium(const AtmosphereModel& m, float altitude) {
  return medium_from(m, DensityProfile(m).at(altitude));
}

namespace {
const char* const kPresetNames[] = {"earth-clear", "earth-hazy", "earth-thin", "earth-dense", "mars-like",
                                    "reference", nullptr};
}

const char* const* atmosphere_preset_names() { return kPresetNames; }

AtmosphereModel atmosphere_preset(const std::string& name) {
  AtmosphereModel m;  // the Earth defaults of DESIGN.md
  if (name == "earth-clear") return m;
  if (name == "earth-hazy") {  // aerosol-laden boundary layer: Mie x10
    m.mie_scattering *= 10.0f;
    m.mie_absorption *= 10.0f;
    return m;
  }
  if (name == "earth-thin") {  // a tenth of every constituent (high-plateau-like thin air)
    m.rayleigh_scattering *= 0.1f;
    m.mie_scattering *= 0.1f;
    m.mie_absorption *= 0.1f;
    m.ozone_absorption *= 0.1f;
    return m;
  }
  if (name == "earth-dense") {  // x10 Rayleigh: multiple scattering dominates, f_ms nears 1
    m.rayleigh_scattering *= 10.0f;
    return m;
  }
  if (name == "mars-like") {
    // Thin CO2 (Rayleigh ~3% of Earth's) and a thick dust haze that absorbs
    // blue (reddish daytime sky); illustrative values, not a fitted Mars model.
    m.bottom_radius = 3389.5e3;
    m.top_radius = 3389.5e3 + 80e3;
    m.rayleigh_scattering = glm::vec3(5.802e-6f, 13.558e-6f, 33.1e-6f) * 0.03f;
    m.rayleigh_scale_height = 11100.0f;
    m.mie_scattering = glm::vec3(44e-6f, 36e-6f, 26e-6f);
    m.mie_absorption = glm::vec3(1e-6f, 5e-6f, 13e-6f);
    m.mie_scale_height = 11100.0f;
    m.mie_g = 0.63f;
    m.ozone_absorption = glm::vec3(0.0f);
    m.ground_albedo = glm::vec3(0.35f, 0.2f, 0.12f);
    m.sun_angular_radius = 0.004675f / 1.524f;  // Mars is 1.524 AU from the sun
    return m;
  }
  if (name == "reference") return reference_atmosphere();
  throw std::out_of_range(name);
}

namespace {
bool non_negative(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0.0f && v.y >= 0.0f &&
         v.z >= 0.0f;
}
}  // namespace

std::string validate_atmosphere(const AtmosphereModel& m) {
  if (!(m.bottom_radius >= 1e3 && m.bottom_radius <= 1e9)) return "planet_radius_m: must be in [1 km, 1e6 km]";
  if (!(m.top_radius > m.bottom_radius))
    return "atmosphere_height_m: the top of the atmosphere must be above the ground (height > 0)";
  if (!(m.top_radius - m.bottom_radius <= 0.5 * m.bottom_radius))
    return "atmosphere_height_m: must not exceed half the planet radius";
  if (!non_negative(m.rayleigh_scattering)) return "rayleigh_scattering: coefficients must be >= 0";
  if (!non_negative(m.mie_scattering)) return "mie_scattering: coefficients must be >= 0";
  if (!non_negative(m.mie_absorption)) return "mie_absorption: coefficients must be >= 0";
  if (!non_negative(m.ozone_absorption)) return "ozone_absorption: coefficients must be >= 0";
  if (!(m.rayleigh_scale_height >= 1.0f)) return "rayleigh_scale_height_m: must be >= 1 m";
  if (!(m.mie_scale_height >= 1.0f)) return "mie_scale_height_m: must be >= 1 m";
  if (!(m.ozone_half_width > 0.0f)) return "ozone_half_width_m: must be > 0";
  if (!std::isfinite(m.ozone_center)) return "ozone_center_m: must be finite";
  if (!(std::abs(m.mie_g) < 1.0f)) return "mie_g: |g| must be < 1";
  if (!(std::abs(m.mie_g2) < 1.0f)) return "mie_g2: |g| must be < 1";
  if (!(m.mie_lobe_weight >= 0.0f && m.mie_lobe_weight <= 1.0f)) return "mie_lobe_weight: must be in [0, 1]";
  if (!(non_negative(m.ground_albedo) && m.ground_albedo.x <= 1.0f && m.ground_albedo.y <= 1.0f &&
        m.ground_albedo.z <= 1.0f))
    return "ground_albedo: must be in [0, 1]";
  if (!(m.sun_angular_radius > 0.0f && m.sun_angular_radius <= 0.2f))
    return "sun_angular_radius_deg: must be in (0, 11.4] degrees";
  return {};
}

AtmosphereSceneConfig parse_atmosphere_scene(const nlohmann::json& section, const std::string& file) {
  ConfigFields f(section, file, "atmosphere");
  AtmosphereSceneConfig c;
  c.preset = f.text("preset", "earth-clear");
  try {
    c.model = atmosphere_preset(c.preset);
  } catch (const std::out_of_range&) {
    std::string names;
    for (const char* const* n = atmosphere_preset_names(); *n; ++n) names += std::string(names.empty() ? "" : ", ") + *n;
    f.fail("preset", "unknown preset \"" + c.preset + "\" (known: " + names + ")");
  }
  AtmosphereModel& m = c.model;
  constexpr double big = 1e30;
  const double radius = f.number("planet_radius_m", m.bottom_radius, -big, big);
  const double height = f.number("atmosphere_height_m", m.atmosphere_height(), -big, big);
  m.bottom_radius = radius;
  m.top_radius = radius + height;
  m.rayleigh_scattering = f.color("rayleigh_scattering", m.rayleigh_scattering, -big, big);
  m.rayleigh_scale_height = float(f.number("rayleigh_scale_height_m", m.rayleigh_scale_height, -big, big));
  m.mie_scattering = f.color("mie_scattering", m.mie_scattering, -big, big);
  m.mie_absorption = f.color("mie_absorption", m.mie_absorption, -big, big);
  m.mie_scale_height = float(f.number("mie_scale_height_m", m.mie_scale_height, -big, big));
  const std::string phase = f.text("mie_phase", m.mie_phase == MiePhaseModel::CornetteShanks ? "cornette-shanks"
                                                                                             : "double-hg");
  if (phase == "cornette-shanks") {
    m.mie_phase = MiePhaseModel::CornetteShanks;
  } else if (phase == "double-hg") {
    // The double HG defaults of the production reference (g1 0.76, g2 -0.4, w 0.9).
    if (m.mie_phase != MiePhaseModel::DoubleHenyeyGreenstein) m.mie_g = 0.76f;
    m.mie_phase = MiePhaseModel::DoubleHenyeyGreenstein;
  } else {
    f.fail("mie_phase", "must be \"cornette-shanks\" or \"double-hg\", got \"" + phase + "\"");
  }
  m.mie_g = float(f.number("mie_g", m.mie_g, -big, big));
  m.mie_g2 = float(f.number("mie_g2", m.mie_g2, -big, big));
  m.mie_lobe_weight = float(f.number("mie_lobe_weight", m.mie_lobe_weight, -big, big));
  m.ozone_absorption = f.color("ozone_absorption", m.ozone_absorption, -big, big);
  m.ozone_center = float(f.number("ozone_center_m", m.ozone_center, -big, big));
  m.ozone_half_width = float(f.number("ozone_half_width_m", m.ozone_half_width, -big, big));
  const float rayleigh_scale = float(f.number("rayleigh_density_scale", 1.0, 0.0, 1e4));
  const float mie_scale = float(f.number("mie_density_scale", 1.0, 0.0, 1e4));
  const float ozone_scale = float(f.number("ozone_density_scale", 1.0, 0.0, 1e4));
  m.rayleigh_scattering *= rayleigh_scale;
  m.mie_scattering *= mie_scale;
  m.mie_absorption *= mie_scale;
  m.ozone_absorption *= ozone_scale;
  m.ground_albedo = f.color("ground_albedo", m.ground_albedo, -big, big);
  m.sun_angular_radius =
      float(f.number("sun_angular_radius_deg", double(m.sun_angular_radius) * 180.0 / kPiD, -big, big) * kPiD /
            180.0);
  c.ground_altitude = f.number("ground_altitude_m", 0.0, -12000.0, 1e7);
  f.finish();
  const std::string problem = validate_atmosphere(m);
  if (!problem.empty()) throw InputError(file, "atmosphere." + problem);
  if (c.ground_altitude >= m.atmosphere_height())
    f.fail("ground_altitude_m", "must be below the top of the atmosphere");
  return c;
}

}  // namespace cr

// Stability sweep of the atmosphere: every valid scene section, at the ends
// of what validation lets through (coefficients and density scales at their
// largest and smallest, scale heights at 1 m, thin and thick atmospheres,
// near-singular phase lobes), bakes LUTs that are finite, non-negative and
// (transmittance) at most one.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "atmosphere_test_util.h"
#include "engine/core/error.h"

using namespace cr;

namespace {

void check_image(const LutImage& img, const std::string& what, bool at_most_one) {
  for (size_t i = 0; i < img.texels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = img.texels[i][c];
      INFO(what << " texel " << i << " channel " << c << " = " << v);
      REQUIRE(std::isfinite(v));
      REQUIRE(v >= 0.0f);
      if (at_most_one) REQUIRE(v <= 1.0f);
    }
}

void check_section(const nlohmann::json& section) {
  INFO("atmosphere section " << section.dump());
  AtmosphereSceneConfig c;
  try {
    c = parse_atmosphere_scene(section, "s.json");
  } catch (const InputError& e) {
    MESSAGE("refused: " << std::string(e.what()));
    return;  // refused with a message: also stable
  }
  JobSystem jobs(2);
  for (const double altitude : {10.0, 20e3, 5e5})
    for (const double zenith : {0.0, 89.0, 95.0}) {
      LutScheduler s(test::small_settings());
      s.set_model(c.model);
      (void)test::run_frame(s, 0, test::camera_at(altitude), test::sun_from_zenith(zenith), jobs);
      check_image(s.transmittance()->image(), "transmittance", true);
      check_image(s.multiscattering()->image(), "multiscattering", false);
      if (s.skyview()) {  // none above the space altitude (per-pixel marching there)
        check_image(s.skyview()->image(), "skyview", false);
        check_image(s.skyview()->mie_image(), "skyview mie", false);
      }
      if (s.aerial_perspective()) {
        check_image(s.aerial_perspective()->luminance(), "aerial perspective luminance", false);
        check_image(s.aerial_perspective()->transmittance(), "aerial perspective transmittance", true);
      }
    }
}

}  // namespace

TEST_CASE("atmosphere stability: extreme valid sections bake finite, bounded LUTs") {
  const double big = 1e30, tiny = 1e-38;
  for (const char* coeff : {"rayleigh_scattering", "mie_scattering", "mie_absorption", "ozone_absorption"})
    for (const double v : {0.0, tiny, 1e-3, 1.0, big}) check_section({{coeff, v}});
  for (const char* scale : {"rayleigh_density_scale", "mie_density_scale", "ozone_density_scale"})
    for (const double v : {0.0, 1e-30, 1e4}) {
      check_section({{scale, v}});
      check_section({{scale, v}, {"rayleigh_scattering", big}, {"mie_scattering", big}});
    }
  for (const char* height : {"rayleigh_scale_height_m", "mie_scale_height_m"})
    for (const double v : {1.0, 1e9}) check_section({{height, v}});
  for (const double g : {-0.99999, 0.99999}) check_section({{"mie_g", g}, {"mie_g2", -g}});
  check_section({{"ozone_half_width_m", 1e-30}});
  check_section({{"ozone_center_m", 1e30}});
  check_section({{"planet_radius_m", 1e3}, {"atmosphere_height_m", 500.0}});
  check_section({{"planet_radius_m", 1e9}, {"atmosphere_height_m", 5e8}});
  check_section({{"planet_radius_m", 1e9}, {"atmosphere_height_m", 1e-3}});
  check_section({{"sun_angular_radius_deg", 1e-30}});
}

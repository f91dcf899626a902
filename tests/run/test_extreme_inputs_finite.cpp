// Whatever a valid scene says, its frames are finite: the fog valley under
// the desktop profile, rendered small with atmosphere and fog sections at the
// ends of their valid ranges (validation refusing one is fine too), has no
// NaN or Inf in its linear colour and distances are never NaN.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/core/error.h"

namespace {

namespace fs = std::filesystem;

void render_finite(const std::function<void(nlohmann::json&)>& edit) {
  const std::string dir = std::string(CR_BINARY_DIR) + "/scenes";
  std::ifstream in(dir + "/fog_valley_sunrise.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["gltf"] = dir + "/default.glb";
  scene["frames"] = 2;
  edit(scene);
  INFO("scene " << scene.dump());
  const fs::path tmp = fs::temp_directory_path() / "cr_extreme_inputs_test";
  fs::create_directories(tmp);
  const std::string path = (tmp / "scene.json").string();
  std::ofstream(path) << scene.dump(2);
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  cr::RunSetup setup;
  try {
    setup = cr::load_run(path, std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", registry, 48, 27, 2);
  } catch (const cr::InputError& e) {
    MESSAGE("refused: " << std::string(e.what()));
    return;
  }
  cr::JobSystem jobs(setup.threads);
  cr::Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
  for (int f = 0; f < 2; ++f) {
    renderer.render_frame(f);
    const cr::FrameBuffers& b = renderer.buffers();
    for (size_t i = 0; i < b.color.size(); ++i) {
      INFO("frame " << f << " pixel " << i);
      REQUIRE(std::isfinite(b.color[i].x));
      REQUIRE(std::isfinite(b.color[i].y));
      REQUIRE(std::isfinite(b.color[i].z));
      REQUIRE(b.color[i].x >= 0.0f);
      REQUIRE(!std::isnan(b.distance[i]));
    }
  }
}

}  // namespace

TEST_CASE("extreme inputs: atmosphere coefficients, scales and phase lobes at their limits render finite frames") {
  for (const char* key : {"rayleigh_scattering", "mie_scattering", "mie_absorption", "ozone_absorption"})
    for (const double v : {0.0, 1e-38, 1e30})
      render_finite([&](nlohmann::json& s) { s["atmosphere"][key] = v; });
  for (const char* key : {"rayleigh_density_scale", "mie_density_scale", "ozone_density_scale"})
    render_finite([&](nlohmann::json& s) {
      s["atmosphere"][key] = 1e4;
      s["atmosphere"]["rayleigh_scattering"] = 1e30;
      s["atmosphere"]["mie_scattering"] = 1e30;
    });
  render_finite([](nlohmann::json& s) {
    s["atmosphere"]["mie_g"] = 0.99999;
    s["atmosphere"]["mie_g2"] = -0.99999;
  });
  render_finite([](nlohmann::json& s) {
    s["atmosphere"]["rayleigh_scale_height_m"] = 1.0;
    s["atmosphere"]["mie_scale_height_m"] = 1.0;
  });
  render_finite([](nlohmann::json& s) { s["atmosphere"]["sun_angular_radius_deg"] = 1e-30; });
}

TEST_CASE("extreme inputs: fog at its shortest and longest mean free paths and sharpest lobes renders finite frames") {
  for (const double mfp : {1e-3, 1e30})
    for (const double g : {-0.99, 0.99})
      render_finite([&](nlohmann::json& s) {
        s["fog"]["height_fog"]["mean_free_path"] = mfp;
        s["fog"]["anisotropy"] = g;
      });
  render_finite([](nlohmann::json& s) { s["sun"]["illuminance"] = 1e30; });
  render_finite([](nlohmann::json& s) { s["exposure_ev100"] = -100; });
}

// A run's memory is estimated before anything large is allocated: frame
// buffers, multisampled edges, shadow maps, plugin LUTs and froxel grids are
// charged as the run loads, and an input that asks for more than the limit is
// refused naming its file and field, never as std::bad_alloc. The estimate is
// an upper bound of what a frame really takes.
#include <doctest/doctest.h>

#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/core/error.h"

namespace {

namespace fs = std::filesystem;

// The desktop profile with `edit` applied, written to a temporary file.
std::string edited_profile(const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
  std::ifstream in(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json");
  nlohmann::json p = nlohmann::json::parse(in);
  edit(p);
  const fs::path dir = fs::temp_directory_path() / "cr_memory_limits_test";
  fs::create_directories(dir);
  const std::string path = (dir / (name + ".json")).string();
  std::ofstream(path) << p.dump(2);
  return path;
}

std::string fog_scene() { return std::string(CR_BINARY_DIR) + "/scenes/fog_valley_sunrise.json"; }

// The InputError message load_run gives, "" when it loads.
std::string refusal(const std::string& profile, int w, int h, size_t limit) {
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  try {
    (void)cr::load_run(fog_scene(), profile, registry, w, h, 1, {}, limit);
  } catch (const cr::InputError& e) {
    CHECK(e.file() == profile);
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Unused in sanitizer builds, which skip the test that reads it.
[[maybe_unused]] long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

}  // namespace

TEST_CASE("memory limits: a frame too large for the limit is refused naming the profile's field") {
  const std::string profile = edited_profile("desktop", [](nlohmann::json&) {});
  const std::string msg = refusal(profile, 16384, 16384, size_t(4) << 30);
  CHECK(contains(msg, "resolution (frame buffers of 16384x16384) needs 7.75 GiB"));
  CHECK(contains(msg, "beyond the memory limit of 4.00 GiB"));
  // Multisampling's edges are charged at their worst: the 4x profile's
  // 1280x720 frames fit 1 GiB, not 256 MiB.
  CHECK(refusal(profile, 0, 0, size_t(1) << 30).empty());
  CHECK(contains(refusal(profile, 0, 0, size_t(256) << 20), "antialiasing (4 samples per pixel at 1280x720)"));
}

TEST_CASE("memory limits: a froxel grid and an aerial-perspective LUT too large are refused before allocation") {
  const std::string fog = edited_profile("fog1", [](nlohmann::json& p) {
    p["fog"]["froxel_size_px"] = 1;
    p["fog"]["slices"] = 1024;
  });
  CHECK(contains(refusal(fog, 0, 0, size_t(8) << 30),
                 "fog.froxel_size_px (froxel grid of 921600 columns x 1024 slices) needs 77.34 GiB"));
  const std::string ap = edited_profile("ap512", [](nlohmann::json& p) {
    p["atmosphere"]["aerial_perspective_lut"] = {{"width", 512}, {"height", 512}, {"depth", 512}};
  });
  CHECK(contains(refusal(ap, 0, 0, size_t(8) << 30),
                 "atmosphere.aerial_perspective_lut.width (aerial-perspective LUT 512x512x512) needs 14.03 GiB"));
}

TEST_CASE("memory limits: the estimate bounds what a run really takes") {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  MESSAGE("skipped: sanitizer allocators add shadow memory and quarantine the estimate does not count");
#else
  // A froxel grid large enough to dominate: 1-pixel froxels, 64 slices at
  // 320x180 (3.7 million froxels).
  const std::string profile = edited_profile("fog_big", [](nlohmann::json& p) {
    p["fog"]["froxel_size_px"] = 1;
    p["fog"]["slices"] = 64;
  });
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const long before = peak_rss_kib();
  const cr::RunSetup setup = cr::load_run(fog_scene(), profile, registry, 320, 180, 2, {}, 0);
  cr::JobSystem jobs(setup.threads);
  cr::Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
  for (int f = 0; f < 2; ++f) renderer.render_frame(f);
  const double grown = double(peak_rss_kib() - before) * 1024.0;
  const double estimate = double(setup.memory.total());
  MESSAGE("peak grew " << grown / 1048576.0 << " MiB, estimate " << estimate / 1048576.0 << " MiB");
  CHECK(grown <= estimate);
  CHECK(grown >= 0.3 * estimate);  // an upper bound, not a wild one
#endif
}

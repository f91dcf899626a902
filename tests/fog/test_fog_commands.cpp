// The fog commands: the turning-sun scene that fog-temporal and fog-bench
// share, a small run of each, and their input errors; fog-accuracy's
// measurement against the ray-marched reference.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/glm.hpp>

#include "engine/core/error.h"
#include "engine/render/frame_view.h"
#include "fog/tools/fog_accuracy.h"
#include "fog/tools/fog_command_common.h"
#include "fog/tools/fog_commands.h"
#include "fog/fog_plugin.h"
#include "tests/output/scratch_dir.h"

using namespace cr;

namespace {

const std::string kVolumes = std::string(CR_BINARY_DIR) + "/scenes/fog_volumes.json";

PluginRegistry fog_registry() {
  PluginRegistry r;
  register_fog_plugin(r);
  return r;
}

}  // namespace

TEST_CASE("the turning sun starts at frame 0's sun and turns only its azimuth") {
  SceneDescription scene;
  scene.sun.illuminance = 100000.0f;
  FrameView first;
  first.sun_direction = sun_direction(155.0f, 7.0f);
  first.sun_illuminance = glm::vec3(100000.0f, 90000.0f, 80000.0f);
  const SceneDescription turning = with_turning_sun(scene, first, 24, 2.0);
  REQUIRE(turning.sun.keys.size() == 2);
  const SunKey &a = turning.sun.keys[0], &b = turning.sun.keys[1];
  CHECK(a.frame == 0);
  CHECK(b.frame == 23);
  CHECK(a.azimuth_deg == doctest::Approx(155.0).epsilon(1e-5));
  CHECK(b.azimuth_deg - a.azimuth_deg == doctest::Approx(46.0).epsilon(1e-5));
  CHECK(a.elevation_deg == doctest::Approx(7.0).epsilon(1e-4));
  CHECK(b.elevation_deg == a.elevation_deg);
  CHECK(glm::length(sun_direction(a.azimuth_deg, a.elevation_deg) - first.sun_direction) < 1e-5f);
  CHECK(glm::length(turning.sun.color * turning.sun.illuminance - first.sun_illuminance) < 0.1f);
}

TEST_CASE("fog-bench and fog-temporal run on a small view; bad input is a clear error") {
  REQUIRE(std::filesystem::exists(kVolumes));
  const PluginRegistry registry = fog_registry();
  // A profile with only the fog's section (the registry has no other plugin).
  const test::ScratchDir dir("fog-commands");
  std::ofstream(dir.file("small.json")) << R"({"resolution": [64, 36], "shadow_map_size": 256, "fog": {"slices": 16}})";
  const std::vector<std::string> small = {"--profile", dir.file("small.json"), "--threads", "2"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.end(), small.begin(), small.end());
    return args;
  };
  CHECK(fog_bench_command(with({kVolumes, "--frames", "3", "--sun-turn", "1"}), registry) == 0);
  CHECK(fog_temporal_command(with({kVolumes, "--frames", "9", "--sun-turn", "3"}), registry) == 0);
  CHECK_THROWS_AS(fog_bench_command(with({kVolumes, "--sun-turn", "abc"}), registry), UsageError);
  CHECK_THROWS_AS(fog_temporal_command(with({kVolumes, "--sun-turn", "500"}), registry), UsageError);
  CHECK_THROWS_AS(fog_temporal_command(with({kVolumes, "--frames", "8"}), registry), UsageError);
  const std::string no_fog = std::string(CR_BINARY_DIR) + "/scenes/engine_only.json";
  CHECK_THROWS_AS(fog_bench_command(with({no_fog}), registry), InputError);
}

TEST_CASE("fog-accuracy: twice the froxel resolution is closer to the ray-marched reference") {
  REQUIRE(std::filesystem::exists(kVolumes));
  const PluginRegistry registry = fog_registry();
  const test::ScratchDir dir("fog-accuracy");
  std::ofstream(dir.file("small.json"))
      << R"({"resolution": [256, 144], "shadow_map_size": 512, "fog": {"slices": 32}})";
  ArgParser args("fog-accuracy", "", "");
  add_fog_command_options(args);
  REQUIRE(args.parse({kVolumes, "--profile", dir.file("small.json")}, 1, 1));
  const FogRun run = load_fog_run(args, registry);
  JobSystem jobs(2);
  const FogAccuracy a = measure_fog_accuracy(run, registry, jobs, 0, 32, 7);
  CHECK(a.width == 256);
  CHECK(a.height == 144);
  CHECK(a.reference_ms > 0.0);
  REQUIRE(a.rows.size() == 3);
  const FogAccuracyRow &temporal = a.rows[0], &single = a.rows[1], &fine = a.rows[2];
  CHECK(temporal.config == "temporal");
  CHECK(single.nx == 32);
  CHECK(single.nz == 32);
  CHECK(fine.nx == 2 * single.nx);
  CHECK(fine.ny == 2 * single.ny);
  CHECK(fine.nz == 2 * single.nz);
  for (const FogAccuracyRow& r : a.rows) {
    CAPTURE(r.config);
    CHECK(std::isfinite(r.error.mean));
    CHECK(r.error.mean > 0.0);  // a froxel grid is not the per-pixel march
    CHECK(r.error.mean < 0.05);
    CHECK(r.error.p95 < 0.1);
  }
  // The method converges on the reference: measured 0.0117 against 0.0211.
  CHECK(fine.error.mean < 0.75 * single.error.mean);
  CHECK(fine.error.p95 < 0.75 * single.error.p95);
  CHECK_THROWS_AS(fog_accuracy_command({kVolumes, "--profile", dir.file("small.json"), "--samples", "0"}, registry),
                  UsageError);
}

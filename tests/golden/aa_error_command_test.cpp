// `cpurender aa-error` as a command: it renders the reference and each mode,
// writes its JSON, and multisampling measurably lowers the edge error.
#include <doctest/doctest.h>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

TEST_CASE("aa-error: msaa4 has less edge error than none against the supersampled frame; bad modes are usage errors") {
  cr::test::ScratchDir dir("aa-error");
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::string scene = std::string(CR_BINARY_DIR) + "/scenes/default.json";
  const std::string json = dir.file("aa.json");
  const std::string profile = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";
  REQUIRE(cr::antialiasing_command({scene, "--profile", profile, "--resolution", "160x90", "--modes", "none,msaa4", "--factor", "4",
                                    "--timing-frames", "1", "--rounds", "1", "--threads", "2", "--json", json},
                                   registry) == 0);
  const nlohmann::json out = cr::load_json_file(json);
  CHECK(out["reference_samples"] == 16);
  CHECK(out["edge_pixels"].get<int>() > 100);
  REQUIRE(out["modes"].size() == 2);
  const nlohmann::json &none = out["modes"][0], &msaa4 = out["modes"][1];
  CHECK(none["mode"] == "none");
  CHECK(msaa4["edge_mean_codes"].get<double>() < 0.7 * none["edge_mean_codes"].get<double>());
  CHECK(msaa4["edge_p95_codes"].get<double>() < none["edge_p95_codes"].get<double>());
  CHECK(msaa4["pass_ms_2t"].contains("geometry"));
  CHECK_THROWS_AS(cr::antialiasing_command({scene, "--profile", profile, "--modes", "msaa3"}, registry), cr::UsageError);
  CHECK_THROWS_AS(cr::antialiasing_command({scene, "--profile", profile, "--resolution", "8192x8192"}, registry), cr::UsageError);
}

// `cpurender sweep --truth`: each module's error against its own ground truth
// (the path-traced sky, the ray-marched fog), recorded per point; references
// rendered once and reused; scenes without a module have no entry.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/command_registry.h"
#include "engine/cli/commands.h"
#include "engine/cli/module_truth.h"
#include "engine/cli/sweep_truth.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

namespace {

// The plugins and their tools, as cpurender registers them.
struct Builtins {
  cr::PluginRegistry plugins;
  cr::CommandRegistry commands;
  cr::ModuleTruthRegistry truths;
  Builtins() {
    cr::register_builtin_plugins(plugins);
    cr::register_builtin_tools(commands, truths, plugins);
  }
};

// The shipped scenes, beside the generated default.glb they name.
std::string shipped_scene(const std::string& name) {
  return (std::filesystem::path(CR_BINARY_DIR) / "scenes" / (name + ".json")).string();
}
const std::string kDesktop = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";

// Cached truth references (*.sky.exr, *.fog.exr) in a sweep's references/.
size_t cached(const std::string& out, const std::string& suffix) {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(out + "/references"))
    n += e.path().filename().string().ends_with(suffix);
  return n;
}

// A tiny sweep: 32x18 (the scenes' sky and fog cover it), one frame.
std::vector<std::string> tiny_sweep(const std::string& scene, const std::string& axis, const std::string& out) {
  return {scene, "--base", kDesktop, "--axis", axis, "--resolution", "32x18", "--frames", "1", "--warmup", "0",
          "--threads", "2", "--out", out};
}

}  // namespace

TEST_CASE("sweep truth: --truth and --truth-setting are checked, a malformed value is a usage error") {
  const Builtins b;
  REQUIRE(b.truths.find("atmosphere") != nullptr);
  REQUIRE(b.truths.find("fog") != nullptr);
  CHECK(cr::select_truths(b.truths, {"all"}, {}).modules.size() == 2);
  CHECK(cr::select_truths(b.truths, {"none"}, {}).modules.empty());
  const cr::SweepTruths fog = cr::select_truths(b.truths, {"fog"}, {"fog.samples=16"});
  REQUIRE(fog.modules.size() == 1);
  CHECK(fog.settings["fog"]["samples"] == 16);
  CHECK(fog.definition()["modules"] == nlohmann::json::array({"fog"}));
  for (const std::vector<std::string>& which :
       std::vector<std::vector<std::string>>{{}, {"sky"}, {"fog", "fog"}, {"all", "fog"}, {"fog", ""}})
    CHECK_THROWS_AS(cr::select_truths(b.truths, which, {}), cr::UsageError);
  for (const char* setting : {"fog.samples", "fog.samples=", "fog.samples=1.5", "fog.samples=x", "fog.nope=1",
                              "atmosphere.paths=8", "samples=8"})
    CHECK_THROWS_AS(cr::select_truths(b.truths, {"fog"}, {setting}), cr::UsageError);
  // Through the command: before anything is rendered.
  cr::test::ScratchDir dir("sweep-truth-usage");
  std::vector<std::string> args = tiny_sweep(shipped_scene("default"), "antialiasing=none", dir.file("out"));
  for (const std::vector<std::string>& extra : std::vector<std::vector<std::string>>{
           {"--truth", "atmosphere,clouds"}, {"--truth", ""}, {"--truth-setting", "atmosphere.paths=0"}}) {
    std::vector<std::string> bad = args;
    bad.insert(bad.end(), extra.begin(), extra.end());
    CHECK_THROWS_AS(cr::sweep_command(bad, b.plugins, b.truths), cr::UsageError);
  }
}

TEST_CASE("sweep truth: more wavelengths are closer to the path-traced sky, whose reference is rendered once and reused") {
  const Builtins b;
  cr::test::ScratchDir dir("sweep-truth-sky");
  const std::string out = dir.file("out");
  std::vector<std::string> args = tiny_sweep(shipped_scene("sky_earth_noon"), "atmosphere.spectral_samples=3,6", out);
  for (const char* s : {"atmosphere.panorama_width=16", "atmosphere.panorama_height=8", "atmosphere.paths=512"})
    args.insert(args.end(), {"--truth-setting", s});
  REQUIRE(cr::sweep_command(args, b.plugins, b.truths) == 0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  REQUIRE(doc["points"].size() == 2);
  const nlohmann::json& rgb = doc["points"][0]["module_error"];
  const nlohmann::json& six = doc["points"][1]["module_error"];
  REQUIRE(rgb.contains("atmosphere"));
  CHECK_FALSE(rgb.contains("fog"));  // the scene has no fog
  CHECK(rgb["atmosphere"]["reference"] == "path-traced spectral sky, 512 paths, 16x8 panorama");
  CHECK(rgb["atmosphere"]["noise"].get<double>() > 0.0);
  CHECK(rgb["atmosphere"]["rel_luminance_p95"].get<double>() >= rgb["atmosphere"]["rel_luminance_mean"].get<double>());
  // Three wavelengths miss the spectral sky by more than six do (about 4% against 2-3% here).
  CHECK(six["atmosphere"]["rel_luminance_mean"].get<double>() < rgb["atmosphere"]["rel_luminance_mean"].get<double>());
  CHECK(rgb["atmosphere"]["reference_cached"] == false);
  CHECK(six["atmosphere"]["reference_cached"] == true);
  CHECK(cached(out, ".sky.exr") == 1);
  const std::string csv = cr::read_file_bytes(out + "/sweep.csv");
  CHECK(csv.find(",flip_mean,atmosphere_truth_mean,atmosphere_truth_p95,fog_truth_mean,fog_truth_p95,") !=
        std::string::npos);

  // --resume with one more value keeps the rows (truth included) and reads the cached reference.
  std::vector<std::string> more = args;
  more[4] = "atmosphere.spectral_samples=3,6,9";
  more.push_back("--resume");
  REQUIRE(cr::sweep_command(more, b.plugins, b.truths) == 0);
  const nlohmann::json resumed = cr::load_json_file(out + "/sweep.json");
  REQUIRE(resumed["points"].size() == 3);
  CHECK(resumed["points"][0] == doc["points"][0]);
  CHECK(resumed["points"][2]["module_error"]["atmosphere"]["reference_cached"] == true);
  CHECK(cached(out, ".sky.exr") == 1);
  // A sweep run again from the start gets the same errors from the cached reference.
  REQUIRE(cr::sweep_command(args, b.plugins, b.truths) == 0);
  const nlohmann::json again = cr::load_json_file(out + "/sweep.json");
  for (size_t i = 0; i < 2; ++i)
    for (const char* k : {"rel_luminance_mean", "rel_luminance_p95", "noise"})
      CHECK(again["points"][i]["module_error"]["atmosphere"][k] == doc["points"][i]["module_error"]["atmosphere"][k]);
  // Another truth setting is another sweep: --resume refuses it.
  std::vector<std::string> other = more;
  other.insert(other.end(), {"--truth-setting", "atmosphere.paths=256"});
  CHECK_THROWS_AS(cr::sweep_command(other, b.plugins, b.truths), cr::InputError);
}

TEST_CASE("sweep truth: finer froxels are closer to the ray-marched fog, and --truth none measures nothing") {
  const Builtins b;
  cr::test::ScratchDir dir("sweep-truth-fog");
  const std::string out = dir.file("out");
  std::vector<std::string> args = tiny_sweep(shipped_scene("fog_valley_flythrough"), "fog.froxel_size_px=4,16", out);
  args.insert(args.end(), {"--resolution", "64x36", "--truth", "fog", "--truth-setting", "fog.samples=32",
                           "--truth-setting", "fog.warmup=7"});
  REQUIRE(cr::sweep_command(args, b.plugins, b.truths) == 0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  REQUIRE(doc["points"].size() == 2);
  const nlohmann::json& fine = doc["points"][0]["module_error"];
  const nlohmann::json& coarse = doc["points"][1]["module_error"];
  CHECK_FALSE(fine.contains("atmosphere"));  // not asked for
  REQUIRE(fine.contains("fog"));
  CHECK(fine["fog"]["noise"].is_null());  // a deterministic quadrature
  CHECK(fine["fog"]["reference"] ==
        "per-pixel ray-marched fog, 32 samples, 64x36, temporal grid after 7 frames of history");
  // 4-pixel froxels against 16-pixel ones: about 4% against 11% here.
  CHECK(fine["fog"]["rel_luminance_mean"].get<double>() * 2 < coarse["fog"]["rel_luminance_mean"].get<double>());
  // The froxel size is not what the reference depends on: one reference for both.
  CHECK(cached(out, ".fog.exr") == 1);
  CHECK(coarse["fog"]["reference_cached"] == true);
  CHECK(cr::read_file_bytes(out + "/sweep.csv").find(",flip_mean,fog_truth_mean,fog_truth_p95,") != std::string::npos);

  // --truth none: no module_error, no truth columns, no truth reference.
  const std::string none = dir.file("none");
  std::vector<std::string> plain = tiny_sweep(shipped_scene("fog_valley_flythrough"), "fog.froxel_size_px=16", none);
  plain.insert(plain.end(), {"--truth", "none"});
  REQUIRE(cr::sweep_command(plain, b.plugins, b.truths) == 0);
  const nlohmann::json nothing = cr::load_json_file(none + "/sweep.json");
  CHECK_FALSE(nothing["points"][0].contains("module_error"));
  CHECK(cr::read_file_bytes(none + "/sweep.csv").find("_truth_") == std::string::npos);
  CHECK(cached(none, ".fog.exr") + cached(none, ".sky.exr") == 0);
}

TEST_CASE("sweep truth: a scene with neither sky nor fog has no module error") {
  const Builtins b;
  cr::test::ScratchDir dir("sweep-truth-engine");
  const std::string out = dir.file("out");
  REQUIRE(cr::sweep_command(tiny_sweep(shipped_scene("engine_only"), "antialiasing=none", out), b.plugins, b.truths) ==
          0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  CHECK(doc["truth"]["modules"] == nlohmann::json::array({"atmosphere", "fog"}));
  CHECK(doc["points"][0]["module_error"] == nlohmann::json::object());
  CHECK(cached(out, ".fog.exr") + cached(out, ".sky.exr") == 0);
}

// `cpurender sweep`: its axes and points, and the command end to end: one row
// per point with times and error, a reference rendered once, --resume.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/cli/module_truth.h"
#include "engine/cli/sweep_points.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

using cr::SweepAxis;
using cr::SweepPoint;

namespace {
// These sweeps measure no module against its ground truth (sweep_truth_test.cpp does).
const cr::ModuleTruthRegistry no_sweep_truths;
}  // namespace

TEST_CASE("sweep axes: typed values, WxH resolutions, clear errors") {
  const SweepAxis a = cr::parse_sweep_axis("atmosphere.spectral_samples=3,6");
  CHECK(a.key == "atmosphere.spectral_samples");
  REQUIRE(a.values.size() == 2);
  CHECK(a.values[0] == 3);
  CHECK(cr::parse_sweep_axis("antialiasing=none,msaa4").values[1] == "msaa4");
  CHECK(cr::parse_sweep_axis("fog.temporal=true").values[0] == true);
  CHECK(cr::parse_sweep_axis("resolution=960x540").values[0] == nlohmann::json::array({960, 540}));
  for (const char* bad : {"noequals", "=1,2", "a..b=1", "a=1,,2", "a=1,1", "resolution=960", "resolution=0x5"})
    CHECK_THROWS_AS(cr::parse_sweep_axis(bad), cr::UsageError);
}

TEST_CASE("sweep points: the cross product, first axis slowest, applied to a profile") {
  const std::vector<SweepPoint> points =
      cr::sweep_points({cr::parse_sweep_axis("a.b=1,2"), cr::parse_sweep_axis("c=x,y,z")});
  REQUIRE(points.size() == 6);
  CHECK(points[0].id() == "a.b=1;c=x");
  CHECK(points[1].id() == "a.b=1;c=y");
  CHECK(points[3].id() == "a.b=2;c=x");
  CHECK_THROWS_AS(cr::sweep_points({cr::parse_sweep_axis("a=1"), cr::parse_sweep_axis("a=2")}), cr::UsageError);
  const nlohmann::json profile = {{"name", "p"}, {"a", {{"keep", 7}}}};
  const nlohmann::json patched = cr::apply_sweep_point(profile, points[4]);
  CHECK(patched["a"]["b"] == 2);
  CHECK(patched["a"]["keep"] == 7);  // the rest of the section stays
  CHECK(patched["c"] == "y");
  CHECK_THROWS_AS(cr::apply_sweep_point({{"name", 5}}, cr::sweep_points({cr::parse_sweep_axis("name.x=1")})[0]),
                  cr::InputError);
  const SweepPoint t = cr::sweep_points({cr::parse_sweep_axis("threads=2")})[0];
  CHECK(cr::sweep_point_threads(t, 8) == 2);
  CHECK(cr::apply_sweep_point(profile, t) == profile);  // "threads" is not a profile key
}

TEST_CASE("sweep: a row per point with times and error, the reference rendered once, --resume keeps finished points") {
  cr::test::ScratchDir dir("sweep");
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::string scene = std::string(CR_BINARY_DIR) + "/scenes/default.json";
  const std::string profile = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";
  const std::string out = dir.file("out");
  const std::vector<std::string> args = {scene,       "--base",   profile, "--axis", "antialiasing=none,msaa4",
                                         "--resolution", "96x54", "--frames", "2",    "--warmup",
                                         "0",           "--threads", "2",   "--out",  out};
  REQUIRE(cr::sweep_command(args, registry, no_sweep_truths) == 0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  REQUIRE(doc["points"].size() == 2);
  for (const nlohmann::json& row : doc["points"]) {
    CHECK(row["frame_ms_p50"].get<double>() > 0.0);
    CHECK(row["passes"].contains("geometry"));
    CHECK(row["error"]["rel_luminance_mean"].get<double>() >= 0.0);
    CHECK(row["error"]["flip_mean"].get<double>() < 0.2);
  }
  // Against the 8x-multisampled reference, 4x has less error than none.
  CHECK(doc["points"][1]["error"]["flip_mean"].get<double>() < doc["points"][0]["error"]["flip_mean"].get<double>());
  const std::string csv = cr::read_file_bytes(out + "/sweep.csv");
  CHECK(csv.rfind("point,antialiasing,threads,frame_ms_p50", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
  // One reference (its profile, linear and displayed frames), cached for the next run.
  auto references = [&] {
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(out + "/references")) n += e.path().extension() == ".json";
    return n;
  };
  CHECK(references() == 1);

  // --resume with one more value: only the new point renders, the old rows stay as they were.
  std::vector<std::string> more = args;
  more[4] = "antialiasing=none,msaa4,msaa2";
  more.push_back("--resume");
  REQUIRE(cr::sweep_command(more, registry, no_sweep_truths) == 0);
  const nlohmann::json resumed = cr::load_json_file(out + "/sweep.json");
  REQUIRE(resumed["points"].size() == 3);
  CHECK(resumed["points"][0] == doc["points"][0]);
  CHECK(resumed["points"][1] == doc["points"][1]);
  CHECK(resumed["points"][2]["point"] == "antialiasing=msaa2");
  CHECK(references() == 1);
  // A different sweep in the same directory is refused.
  std::vector<std::string> other = more;
  other[8] = "3";  // --frames 3
  CHECK_THROWS_AS(cr::sweep_command(other, registry, no_sweep_truths), cr::InputError);
  // No axis, or a key the profile rejects.
  CHECK_THROWS_AS(cr::sweep_command({scene, "--base", profile, "--out", out}, registry, no_sweep_truths), cr::UsageError);
  CHECK_THROWS_AS(cr::sweep_command({scene, "--base", profile, "--axis", "no_such_key=1", "--resolution", "32x18",
                                     "--frames", "1", "--warmup", "0", "--out", dir.file("bad")},
                                    registry, no_sweep_truths),
                  cr::InputError);
}

TEST_CASE("sweep listed points: --point LABEL=PROFILE, a sweep file, auto points with their plan, amortised pass means") {
  cr::test::ScratchDir dir("sweep-listed");
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::string scene = std::string(CR_BINARY_DIR) + "/scenes/default.json";
  const std::string profile = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";
  const std::string table = std::string(CR_SOURCE_DIR) + "/profiles/planner/auto_table.json";
  const std::string file = dir.file("points.json");
  cr::write_file_atomic(file, nlohmann::json{{"points", {{{"label", "desktop, no AA"}, {"profile", profile},
                                                          {"settings", {{"antialiasing", "none"}}}}}}}
                                  .dump());
  const std::string out = dir.file("out");
  const std::vector<std::string> args = {scene, "--base", profile, "--points", file, "--point", "desktop=" + profile,
                                         "--point", "auto=auto:" + profile, "--plan-table", table, "--resolution", "96x54",
                                         "--frames", "3", "--warmup", "0", "--threads", "2", "--out", out};
  REQUIRE(cr::sweep_command(args, registry, no_sweep_truths) == 0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  REQUIRE(doc["points"].size() == 3);
  CHECK(doc["points"][0]["label"] == "desktop, no AA");
  CHECK(doc["points"][0]["settings"]["antialiasing"] == "none");
  CHECK(doc["points"][1]["label"] == "desktop");
  const nlohmann::json& a = doc["points"][2];
  CHECK(a["label"] == "auto");
  REQUIRE(a.contains("plan"));
  CHECK(a["plan"]["facts"]["frames"] == 3);
  // The profile the auto point rendered is written beside the others.
  CHECK(cr::load_json_file(a["profile"].get<std::string>())["name"] == "auto");
  // "mean" spreads a pass over every measured frame; p50 is of the frames it ran.
  for (const nlohmann::json& row : doc["points"])
    for (const auto& [name, pass] : row["passes"].items()) {
      CHECK(pass["mean"].get<double>() <= pass["p99"].get<double>() + 1e-9);
      CHECK(pass["p95"].get<double>() <= pass["p99"].get<double>());
    }
  const std::string csv = cr::read_file_bytes(out + "/sweep.csv");
  CHECK(csv.find("\ndesktop,") != std::string::npos);
  // A second sweep reads the cached reference (float EXR): the same errors as the render it cached.
  REQUIRE(cr::sweep_command(args, registry, no_sweep_truths) == 0);
  const nlohmann::json again = cr::load_json_file(out + "/sweep.json");
  for (size_t i = 0; i < 3; ++i) CHECK(again["points"][i]["error"] == doc["points"][i]["error"]);
  // Two points of one name, and keys set on an auto point, are refused.
  CHECK_THROWS_AS(cr::sweep_command({scene, "--point", "a=desktop", "--point", "a=mobile", "--out", out}, registry, no_sweep_truths),
                  cr::UsageError);
  CHECK_THROWS_AS(cr::parse_listed_point("noprofile"), cr::UsageError);
  CHECK_THROWS_AS(cr::parse_sweep_file(nlohmann::json{{"points", {{{"profile", "x"}}}}}, "f.json"), cr::InputError);
}

TEST_CASE("sweep --first-frame: points and the reference start cold at that frame of the path") {
  cr::test::ScratchDir dir("sweep_first_frame");
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::string scene = std::string(CR_BINARY_DIR) + "/scenes/default_flythrough.json";
  const std::string profile = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";
  const std::string out = dir.file("out");
  // A point rendering the reference's own profile: zero error only if both render the same frames.
  const std::vector<std::string> args = {scene, "--base", profile, "--reference", profile, "--point",
                                         "same=" + profile, "--axis", "antialiasing=none", "--resolution", "64x36",
                                         "--frames", "1", "--warmup", "1", "--threads", "2", "--first-frame", "20",
                                         "--out", out};
  REQUIRE(cr::sweep_command(args, registry, no_sweep_truths) == 0);
  const nlohmann::json doc = cr::load_json_file(out + "/sweep.json");
  CHECK(doc["first_frame"] == 20);
  REQUIRE(doc["points"].size() == 2);
  // Axis points have no label; the listed point is labelled.
  const bool same_first = doc["points"][0].value("label", "") == "same";
  const nlohmann::json& same = doc["points"][same_first ? 0 : 1];
  CHECK(same["error"]["rel_luminance_mean"].get<double>() == 0.0);
  const nlohmann::json& other = doc["points"][same_first ? 1 : 0];
  CHECK(other["error"]["rel_luminance_mean"].get<double>() > 0.0);
  // Resuming from another frame is another sweep.
  std::vector<std::string> moved = args;
  moved[moved.size() - 3] = "0";
  moved.push_back("--resume");
  CHECK_THROWS_AS(cr::sweep_command(moved, registry, no_sweep_truths), cr::InputError);
}

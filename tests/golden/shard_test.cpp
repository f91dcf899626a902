// Sharded runs (--shard I/N) of sweep, golden and render, joined by `merge`:
// the merged folder holds what the unsharded command writes, mismatched or
// incomplete shards are refused, and --resume renders only what is missing.
#include <doctest/doctest.h>

#include <filesystem>
#include <set>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/cli/golden_command.h"
#include "engine/cli/module_truth.h"
#include "engine/cli/shard.h"
#include "engine/cli/shard_merge.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/output/png_io.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

namespace {

const cr::ModuleTruthRegistry no_truths;

cr::PluginRegistry plugins() {
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  return registry;
}

std::string binary_file(const std::string& rel) { return std::string(CR_BINARY_DIR) + "/" + rel; }

// A row without what differs between two renders of the same point (times, where its profile lies).
nlohmann::json without_timings(nlohmann::json row) {
  for (const char* k : {"frame_ms_p50", "frame_ms_p95", "frame_ms_p99", "passes", "profile"}) row.erase(k);
  return row;
}

void mark_incomplete(const std::string& dir) {
  nlohmann::json m = cr::load_json_file(dir + "/shard.json");
  m["complete"] = false;
  m["done"] = nlohmann::json::array();
  cr::write_file_atomic(dir + "/shard.json", m.dump());
}

}  // namespace

TEST_CASE("shards: I/N parsing, items k mod N, contiguous frame blocks that cover the path once") {
  const cr::Shard s = cr::parse_shard("2/5", "t");
  CHECK(s.index == 2);
  CHECK(s.count == 5);
  for (const char* bad : {"", "3", "5/5", "-1/4", "1/0", "a/4", "1/4x", "1/70000", "1//4"})
    CHECK_THROWS_AS(cr::parse_shard(bad, "t"), cr::UsageError);
  for (int count : {1, 3, 4, 7})
    for (int frames : {1, 5, 12, 48}) {
      std::vector<int> owner(size_t(frames), -1);
      int next = 10;
      for (int i = 0; i < count; ++i) {
        const auto [b, e] = cr::Shard{i, count}.frame_block(10, frames);
        CHECK(b == next);  // contiguous, in order
        CHECK(e - b >= frames / count);
        CHECK(e - b <= frames / count + 1);
        next = e;
        for (size_t k = 0; k < size_t(frames); ++k)
          if (cr::Shard{i, count}.owns(k)) CHECK(owner[k]++ == -1);
      }
      CHECK(next == 10 + frames);
      for (int o : owner) CHECK(o == 0);  // every item in exactly one shard
    }
}

TEST_CASE("sharded sweep: 2 shards merged equal the unsharded sweep; merge refuses missing, foreign and incomplete shards; --resume") {
  cr::test::ScratchDir dir("shard-sweep");
  const cr::PluginRegistry registry = plugins();
  const std::vector<std::string> base = {binary_file("scenes/default.json"), "--base",
                                         std::string(CR_SOURCE_DIR) + "/profiles/desktop.json",
                                         "--axis", "antialiasing=none,msaa2,msaa4", "--resolution", "64x36",
                                         "--frames", "1", "--warmup", "0", "--threads", "2", "--truth", "none"};
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), {"--out", out});
    args.insert(args.end(), extra.begin(), extra.end());
    return cr::sweep_command(args, registry, no_truths);
  };
  REQUIRE(run(dir.file("whole"), {}) == 0);
  REQUIRE(run(dir.file("s0"), {"--shard", "0/2"}) == 0);
  REQUIRE(run(dir.file("s1"), {"--shard", "1/2"}) == 0);
  CHECK(cr::load_json_file(dir.file("s0") + "/sweep.json")["points"].size() == 2);  // points 0 and 2
  CHECK(cr::load_json_file(dir.file("s1") + "/sweep.json")["points"].size() == 1);
  REQUIRE(cr::merge_command({dir.file("s1"), dir.file("s0"), "--out", dir.file("merged")}) == 0);
  nlohmann::json whole = cr::load_json_file(dir.file("whole") + "/sweep.json");
  nlohmann::json merged = cr::load_json_file(dir.file("merged") + "/sweep.json");
  REQUIRE(merged["points"].size() == 3);
  for (size_t i = 0; i < 3; ++i) {
    CHECK(without_timings(merged["points"][i]) == without_timings(whole["points"][i]));  // same bits, same errors
    CHECK(cr::load_json_file(merged["points"][i]["profile"].get<std::string>()) ==
          cr::load_json_file(whole["points"][i]["profile"].get<std::string>()));
  }
  for (const auto& [key, value] : whole.items())  // the sweep's definition as the unsharded run wrote it
    if (key != "points") CHECK(merged.value(key, nlohmann::json()) == value);
  CHECK(merged.size() == whole.size());  // what ran where is in merge.json
  CHECK(cr::load_json_file(dir.file("merged") + "/merge.json")["shards"].size() == 2);
  CHECK(std::filesystem::exists(dir.file("merged") + "/sweep.csv"));

  // Refusals, each naming what is wrong.
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s0"), "--out", dir.file("m2")}), doctest::Contains("missing"),
                       cr::InputError);
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s0"), dir.file("s0"), "--out", dir.file("m2")}),
                       doctest::Contains("twice"), cr::InputError);
  CHECK_THROWS_AS(cr::merge_command({dir.file("whole"), "--out", dir.file("m2")}), cr::InputError);  // not a shard
  REQUIRE(run(dir.file("other"), {"--shard", "1/2", "--frames", "2"}) == 0);
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s0"), dir.file("other"), "--out", dir.file("m2")}),
                       doctest::Contains("\"frames\" differs"), cr::InputError);
  CHECK_THROWS_AS(cr::merge_command({dir.file("s0"), dir.file("s1"), "--out", dir.file("s0")}), cr::UsageError);

  // A shard killed after its first point: merge refuses it, --resume renders only the other.
  nlohmann::json partial = cr::load_json_file(dir.file("s0") + "/sweep.json");
  const nlohmann::json first_row = partial["points"][0];
  partial["points"].erase(1);
  cr::write_file_atomic(dir.file("s0") + "/sweep.json", partial.dump());
  mark_incomplete(dir.file("s0"));
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s0"), dir.file("s1"), "--out", dir.file("m3")}),
                       doctest::Contains("incomplete"), cr::InputError);
  REQUIRE(run(dir.file("s0"), {"--shard", "0/2", "--resume"}) == 0);
  nlohmann::json resumed = cr::load_json_file(dir.file("s0") + "/sweep.json");
  REQUIRE(resumed["points"].size() == 2);
  CHECK(resumed["points"][0] == first_row);  // kept as it was, timings included
  REQUIRE(cr::merge_command({dir.file("s0"), dir.file("s1"), "--out", dir.file("m3")}) == 0);
  // Resuming a folder as another shard is refused.
  CHECK_THROWS_AS(run(dir.file("s0"), {"--shard", "1/2", "--resume"}), cr::InputError);
}

TEST_CASE("sharded golden check: merged report equals the unsharded one; --resume keeps finished cases; --update cannot shard") {
  cr::test::ScratchDir dir("shard-golden");
  const cr::PluginRegistry registry = plugins();
  auto run = [&](const std::string& report, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--dir", std::string(CR_SOURCE_DIR) + "/tests/golden", "--only", "engine_only.*",
                                     "--scenes", binary_file("scenes"), "--profiles", binary_file("profiles"),
                                     "--threads", "2", "--report", report};
    args.insert(args.end(), extra.begin(), extra.end());
    return cr::golden_command(args, registry);
  };
  REQUIRE(run(dir.file("whole"), {}) == 0);
  REQUIRE(run(dir.file("g0"), {"--shard", "0/2"}) == 0);
  REQUIRE(run(dir.file("g1"), {"--shard", "1/2"}) == 0);
  CHECK(cr::merge_command({dir.file("g0"), dir.file("g1"), "--out", dir.file("merged")}) == 0);
  nlohmann::json whole = cr::load_json_file(dir.file("whole") + "/golden_report.json");
  nlohmann::json merged = cr::load_json_file(dir.file("merged") + "/golden_report.json");
  REQUIRE(whole["rows"].size() == 2);  // engine_only under desktop and mobile
  REQUIRE(merged["rows"].size() == 2);
  for (size_t i = 0; i < 2; ++i)
    for (const char* k : {"case", "frame", "status", "metrics", "deterministic", "golden", "thresholds"})
      CHECK(merged["rows"][i][k] == whole["rows"][i][k]);
  CHECK(merged["exit_code"] == 0);

  // --resume renders nothing that finished: the kept rows' times are the first run's.
  REQUIRE(run(dir.file("g0"), {"--shard", "0/2", "--resume"}) == 0);
  nlohmann::json again = cr::load_json_file(dir.file("g0") + "/golden_report.json");
  CHECK(again["rows"][0]["render_ms"] ==
        cr::load_json_file(dir.file("merged") + "/golden_report.json")["rows"][0]["render_ms"]);
  CHECK_THROWS_AS(run(dir.file("u"), {"--update", "--shard", "0/2"}), cr::UsageError);
  // A failing case in one shard makes the merged check fail.
  nlohmann::json report = cr::load_json_file(dir.file("g1") + "/golden_report.json");
  report["rows"][0]["status"] = "FAIL";
  cr::write_file_atomic(dir.file("g1") + "/golden_report.json", report.dump());
  CHECK(cr::merge_command({dir.file("g0"), dir.file("g1"), "--out", dir.file("merged2")}) == 1);
}

TEST_CASE("sharded render: 3 blocks of the fog flythrough equal the unsharded frames; warm-up; --resume; merge refuses") {
  cr::test::ScratchDir dir("shard-render");
  const cr::PluginRegistry registry = plugins();
  const std::string scene = binary_file("scenes/fog_valley_flythrough.json");
  auto run = [&](const std::string& out, std::vector<std::string> extra, bool trace = false) {
    std::vector<std::string> args = {scene, "--profile", binary_file("profiles/desktop.json"), "--resolution", "48x27", "--frames", "9", "--threads", "2",
                                     "--format", "png", "--quiet", "--out", out};
    if (!trace) args.push_back("--no-trace");
    args.insert(args.end(), extra.begin(), extra.end());
    return cr::render_command(args, registry);
  };
  auto same_frames = [&](const std::string& a, const std::string& b, int first, int end) {
    for (int f = first; f < end; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "/frame_%04d.png", f);
      REQUIRE(std::filesystem::exists(a + name));
      REQUIRE(std::filesystem::exists(b + name));
      if (cr::read_file_bytes(a + name) != cr::read_file_bytes(b + name)) return false;
    }
    return true;
  };
  REQUIRE(run(dir.file("whole"), {}) == 0);
  // The scene's plugins ask for more warm-up than 9 frames: each block starts from frame 0.
  for (const char* shard : {"0/3", "1/3", "2/3"})
    REQUIRE(run(dir.file(std::string("r") + shard[0]), {"--shard", shard}) == 0);
  CHECK(cr::load_json_file(dir.file("r2") + "/shard.json")["extra"]["warmup_frames"] == 6);
  REQUIRE(cr::merge_command({dir.file("r0"), dir.file("r1"), dir.file("r2"), "--out", dir.file("merged")}) == 0);
  CHECK(same_frames(dir.file("whole"), dir.file("merged"), 0, 9));  // bit for bit
  nlohmann::json report = cr::load_json_file(dir.file("merged") + "/report.json");
  REQUIRE(report["frames"].size() == 9);
  CHECK(report["summary"]["frames"] == 9);
  CHECK(report["extra"]["render"]["shards"].size() == 3);

  // More shards than frames: the empty blocks render nothing and still merge.
  for (const char* shard : {"0/4", "1/4", "2/4", "3/4"})
    REQUIRE(run(dir.file(std::string("e") + shard[0]), {"--shard", shard, "--frames", "2"}, true) == 0);
  REQUIRE(cr::merge_command({dir.file("e0"), dir.file("e1"), dir.file("e2"), dir.file("e3"), "--out", dir.file("me")}) == 0);
  CHECK(cr::load_json_file(dir.file("me") + "/report.json")["frames"].size() == 2);
  // One trace, a process per shard.
  const nlohmann::json trace = cr::load_json_file(dir.file("me") + "/trace.json");
  std::set<int> pids;
  for (const nlohmann::json& e : trace.value("traceEvents", nlohmann::json::array())) pids.insert(e.value("pid", 0));
  CHECK(pids == std::set<int>{1, 2, 3, 4});
  CHECK(same_frames(dir.file("whole"), dir.file("me"), 0, 2));

  // A short explicit warm-up: the block's first frame starts from a cold
  // history, close to the unsharded frame but not its bits.
  REQUIRE(run(dir.file("cold"), {"--shard", "2/3", "--warmup-frames", "0"}) == 0);
  CHECK_FALSE(same_frames(dir.file("whole"), dir.file("cold"), 6, 7));

  // Killed after its first frame: merge refuses, --resume renders the rest after warming up.
  nlohmann::json r1 = cr::load_json_file(dir.file("r1") + "/report.json");
  r1["status"] = "running";
  r1["frames"].erase(1);
  r1["frames"].erase(1);
  cr::write_file_atomic(dir.file("r1") + "/report.json", r1.dump());
  std::filesystem::remove(dir.file("r1") + "/frame_0005.png");
  mark_incomplete(dir.file("r1"));
  CHECK_THROWS_AS(cr::merge_command({dir.file("r0"), dir.file("r1"), dir.file("r2"), "--out", dir.file("m2")}),
                  cr::InputError);
  REQUIRE(run(dir.file("r1"), {"--shard", "1/3", "--resume"}) == 0);
  nlohmann::json resumed = cr::load_json_file(dir.file("r1") + "/report.json");
  REQUIRE(resumed["frames"].size() == 3);
  CHECK(resumed["frames"][0] == r1["frames"][0]);  // the kept frame's record
  CHECK(resumed["extra"]["render"]["warmup_frames"] == 4);  // from frame 0 up to the first missing one
  REQUIRE(cr::merge_command({dir.file("r0"), dir.file("r1"), dir.file("r2"), "--out", dir.file("m2")}) == 0);
  CHECK(same_frames(dir.file("whole"), dir.file("m2"), 0, 9));
  // A rerun with another command line is refused, as is merging shards of two renders.
  CHECK_THROWS_AS(run(dir.file("r1"), {"--shard", "1/3", "--resume", "--frames", "8"}), cr::InputError);
  REQUIRE(run(dir.file("o2"), {"--shard", "2/3", "--first-frame", "1"}) == 0);
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("r0"), dir.file("r1"), dir.file("o2"), "--out", dir.file("m4")}),
                       doctest::Contains("differs"), cr::InputError);
}

TEST_CASE("merge: malformed shard manifests are input errors naming the file, never a crash") {
  cr::test::ScratchDir dir("shard-bad");
  const cr::ShardManifest good = cr::new_shard_manifest("sweep", cr::Shard{0, 1}, {{"frames", 1}});
  for (const std::string& text :
       {std::string("not json"), std::string("[]"), std::string("{\"format\": \"cpurender-shard\"}"),
        std::string(R"({"format": "cpurender-shard", "command": 5})"),
        [&] { nlohmann::json j = good.to_json(); j["shard"]["index"] = 3; return j.dump(); }(),
        [&] { nlohmann::json j = good.to_json(); j["shard"]["count"] = -2; return j.dump(); }(),
        [&] { nlohmann::json j = good.to_json(); j["items"] = {1, 2}; return j.dump(); }(),
        [&] { nlohmann::json j = good.to_json(); j["complete"] = "yes"; return j.dump(); }()}) {
    std::filesystem::create_directories(dir.file("s"));
    cr::write_file_atomic(dir.file("s") + "/shard.json", text);
    CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s"), "--out", dir.file("m")}), doctest::Contains("shard.json"),
                         cr::InputError);
  }
  // A complete manifest whose outputs are missing.
  nlohmann::json j = good.to_json();
  j["complete"] = true;
  cr::write_file_atomic(dir.file("s") + "/shard.json", j.dump());
  CHECK_THROWS_WITH_AS(cr::merge_command({dir.file("s"), "--out", dir.file("m")}), doctest::Contains("sweep.json"),
                       cr::InputError);
  CHECK_THROWS_AS(cr::merge_command({dir.file("s")}), cr::UsageError);  // no --out
}

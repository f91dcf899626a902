// The golden workflow end to end on a scratch directory: --update writes the
// goldens, a second run passes, a tampered golden fails with heat maps, a
// render failure makes --update write nothing, stale goldens are reported.
// Small renders (48x27, odd so tiles split unevenly) keep it fast under ASan.
#include <doctest/doctest.h>

#include <filesystem>
#include <map>

#include "engine/cli/arg_parser.h"
#include "engine/cli/commands.h"
#include "engine/cli/golden_command.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/output/png_io.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;
namespace fs = std::filesystem;

namespace {

const std::string kDefaultGlb = std::string(CR_BINARY_DIR) + "/scenes/default.glb";

constexpr const char* kTolerances = R"({
  "comment": "test tolerances: 8-bit rounding only",
  "profiles": {
    "default": {"max_abs": 0.02, "rmse": 0.01, "pixel_threshold": 0.0079, "max_fraction": 0.0,
                "flip_mean": 0.05,
                "why": {"max_abs": "a", "rmse": "b", "pixel_threshold": "c", "max_fraction": "d",
                        "flip_mean": "e"}}
  }
})";

// A still scene and a 3-frame camera path (kept frames 0 and 2) over the
// project's generated scene, and one small profile.
struct GoldenFixture {
  ScratchDir root;
  std::string scenes = root.file("scenes"), profiles = root.file("profiles"), golden = root.file("golden"),
              report = root.file("report");
  cr::PluginRegistry registry;

  explicit GoldenFixture(const std::string& name) : root("golden-" + name) {
    cr::register_builtin_plugins(registry);
    fs::create_directories(scenes);
    fs::create_directories(profiles);
    fs::create_directories(golden);
    write(scenes + "/still.json", R"({"gltf": ")" + kDefaultGlb + R"(", "camera": {"gltf_camera": 0},
        "sun": {"azimuth_deg": 120, "elevation_deg": 35}, "ambient": [1250, 1600, 2250]})");
    write(scenes + "/path.json", R"({"gltf": ")" + kDefaultGlb + R"(", "frames": 3,
        "camera": {"keys": [{"frame": 0, "position": [0, 5, 14], "target": [0, 0.6, -96]},
                            {"frame": 2, "position": [4, 6.5, 2], "target": [-20, 1.5, -90]}]},
        "sun": {"azimuth_deg": 140, "elevation_deg": 20}, "ambient": [1250, 1600, 2250]})");
    write(profiles + "/tiny.json", R"({"tile_size": 16, "shadow_map_size": 256, "shadow_distance": 100})");
    write(golden + "/tolerances.json", kTolerances);
  }

  static void write(const std::string& path, const std::string& text) { cr::write_file_atomic(path, text); }

  int run(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--dir", golden, "--scenes", scenes, "--profiles", profiles, "--report", report,
                                     "--resolution", "48x27", "--threads", "3"};
    args.insert(args.end(), extra.begin(), extra.end());
    return cr::golden_command(args, registry);
  }

  nlohmann::json report_json() const { return cr::load_json_file(report + "/golden_report.json"); }
  // By value: a range-for over report_json()["rows"] would outlive the document.
  nlohmann::json rows() const { return report_json()["rows"]; }

  // Every file of the golden directory with its bytes.
  std::map<std::string, std::string> golden_files() const {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::directory_iterator(golden))
      files[e.path().filename().string()] = cr::read_file_bytes(e.path().string());
    return files;
  }

  std::map<std::string, std::string> statuses() const {
    std::map<std::string, std::string> s;
    for (const nlohmann::json& row : rows())
      s[row["case"].get<std::string>() + "@" + std::to_string(row["frame"].get<int>())] = row["status"];
    return s;
  }
};

const std::vector<std::string> kGoldens = {"path.tiny.f0000.png", "path.tiny.f0002.png", "still.tiny.f0000.png"};

// Adds `delta` to the red channel of one pixel of a golden PNG.
void tamper(const std::string& path, int x, int y, int delta) {
  cr::Image8 image = cr::read_png(path, 3);
  uint8_t& red = image.data[(size_t(y) * image.width + x) * 3];
  red = uint8_t(red + delta > 255 ? red - delta : red + delta);
  cr::write_png(path, image);
}

}  // namespace

TEST_CASE("golden --update on an empty directory writes every golden, and a second run passes") {
  GoldenFixture fx("update");
  CHECK(fx.run({"--update"}) == 0);
  for (const std::string& name : kGoldens) {
    CAPTURE(name);
    REQUIRE(fs::exists(fx.golden + "/" + name));
    const cr::Image8 image = cr::read_png(fx.golden + "/" + name);
    CHECK(image.width == 48);
    CHECK(image.height == 27);
  }
  CHECK(fx.golden_files().size() == kGoldens.size() + 1);  // + tolerances.json
  for (const auto& [row, status] : fx.statuses()) CHECK_MESSAGE(status == "ADDED", row);

  CHECK(fx.run() == 0);
  const nlohmann::json report = fx.report_json();
  CHECK(report["mode"] == "check");
  REQUIRE(report["rows"].size() == kGoldens.size());
  for (const nlohmann::json& row : report["rows"]) {
    CHECK(row["status"] == "pass");
    CHECK(row["deterministic"] == true);
    CHECK(row["metrics"]["max_abs"] == 0.0);
    CHECK(row["tolerance_entry"] == "default");
    CHECK(row["render_ms"]["threads_1"].get<double>() > 0.0);
    CHECK(row["render_ms"]["threads_3"].get<double>() > 0.0);
  }
  CHECK(fs::exists(fx.report + "/golden_report.txt"));
  CHECK(report["stale_goldens"].empty());
  // A second update finds nothing to write.
  const auto before = fx.golden_files();
  CHECK(fx.run({"--update"}) == 0);
  CHECK(fx.golden_files() == before);
  for (const auto& [row, status] : fx.statuses()) CHECK_MESSAGE(status == "unchanged", row);
}

TEST_CASE("golden: a tampered golden pixel fails the run with heat maps and --update restores only it") {
  GoldenFixture fx("tamper");
  REQUIRE(fx.run({"--update"}) == 0);
  const auto original = fx.golden_files();
  const std::string victim = fx.golden + "/path.tiny.f0002.png";
  tamper(victim, 30, 12, 120);

  CHECK(fx.run() == 1);
  const auto statuses = fx.statuses();
  CHECK(statuses.at("path.tiny@2") == "FAIL");
  CHECK(statuses.at("path.tiny@0") == "pass");
  CHECK(statuses.at("still.tiny@0") == "pass");
  for (const nlohmann::json& row : fx.rows()) {
    if (row["status"] != "FAIL") {
      CHECK_FALSE(row.contains("diff_image"));
      continue;
    }
    CHECK(row["metrics"]["pixels_over_threshold"] == 1);
    CHECK(row["metrics"]["max_abs"].get<double>() == doctest::Approx(120.0 / 255.0).epsilon(1e-5));
    const cr::Image8 heat = cr::read_png(row["diff_image"].get<std::string>());
    CHECK(heat.width == 48);
    auto brightness = [&](int x, int y) {
      const uint8_t* p = &heat.data[(size_t(y) * heat.width + x) * heat.channels];
      return p[0] + p[1] + p[2];
    };
    CHECK(brightness(30, 12) > brightness(0, 0) + 100);
    CHECK(fs::exists(row["flip_image"].get<std::string>()));
    // The new render beside the heat maps equals the untampered golden.
    CHECK(cr::read_file_bytes(row["new_image"].get<std::string>()) == original.at("path.tiny.f0002.png"));
  }

  CHECK(fx.run({"--update"}) == 0);
  const auto updated = fx.statuses();
  CHECK(updated.at("path.tiny@2") == "UPDATED");
  CHECK(updated.at("path.tiny@0") == "unchanged");
  CHECK(fx.golden_files() == original);
  CHECK(fx.run() == 0);
}

TEST_CASE("golden: a change within tolerance passes and --update keeps it unless --exact") {
  GoldenFixture fx("within");
  REQUIRE(fx.run({"--update"}) == 0);
  const auto original = fx.golden_files();
  const std::string victim = fx.golden + "/still.tiny.f0000.png";
  tamper(victim, 5, 5, 1);  // one code: under the 2-code pixel threshold
  const std::string tampered = cr::read_file_bytes(victim);

  CHECK(fx.run() == 0);
  for (const nlohmann::json& row : fx.rows())
    if (row["case"] == "still.tiny") CHECK(row["metrics"]["max_abs"].get<double>() == doctest::Approx(1.0 / 255.0));
  CHECK(fx.run({"--update"}) == 0);
  CHECK(fx.statuses().at("still.tiny@0") == "kept");
  CHECK(cr::read_file_bytes(victim) == tampered);
  CHECK(fx.run({"--update", "--exact"}) == 0);
  CHECK(fx.statuses().at("still.tiny@0") == "UPDATED");
  CHECK(fx.golden_files() == original);
}

TEST_CASE("golden --update writes nothing when a case fails to render") {
  GoldenFixture fx("render-failure");
  REQUIRE(fx.run({"--update"}) == 0);
  tamper(fx.golden + "/path.tiny.f0002.png", 3, 3, 100);  // would be rewritten
  fs::remove(fx.golden + "/still.tiny.f0000.png");         // would be added
  const auto before = fx.golden_files();
  // A scene whose glTF exists but is corrupt: it fails while loading, after
  // the other cases rendered.
  fx.write(fx.root.file("broken.glb"), "glTF this is not");
  fx.write(fx.scenes + "/zz_broken.json", R"({"gltf": ")" + fx.root.file("broken.glb") + R"("})");

  CHECK(fx.run({"--update"}) == 2);
  CHECK(fx.golden_files() == before);
  const nlohmann::json report = fx.report_json();
  CHECK(report["wrote_goldens"] == false);
  CHECK(report["note"].get<std::string>().find("nothing written") != std::string::npos);
  CHECK(fx.statuses().at("zz_broken.tiny@0") == "ERROR");
  // The check run reports the error as exit 2 too.
  CHECK(fx.run() == 2);
}

TEST_CASE("golden: stale goldens are reported, kept, and deleted only by --update --prune") {
  GoldenFixture fx("stale");
  REQUIRE(fx.run({"--update"}) == 0);
  fs::copy_file(fx.golden + "/still.tiny.f0000.png", fx.golden + "/gone.tiny.f0000.png");
  CHECK(fx.run() == 0);
  CHECK(fx.report_json()["stale_goldens"] == nlohmann::json::array({"gone.tiny.f0000.png"}));
  CHECK(fx.run({"--update"}) == 0);
  CHECK(fs::exists(fx.golden + "/gone.tiny.f0000.png"));
  // --only does not make the other cases' goldens stale.
  CHECK(fx.run({"--update", "--prune", "--only", "still.*"}) == 0);
  CHECK(fx.statuses().size() == 1);
  CHECK_FALSE(fs::exists(fx.golden + "/gone.tiny.f0000.png"));
  CHECK(fs::exists(fx.golden + "/path.tiny.f0002.png"));
}

TEST_CASE("golden: a missing golden fails the check run and writes the new render") {
  GoldenFixture fx("missing");
  REQUIRE(fx.run({"--update"}) == 0);
  fs::remove(fx.golden + "/still.tiny.f0000.png");
  CHECK(fx.run() == 1);
  for (const nlohmann::json& row : fx.rows())
    if (row["case"] == "still.tiny") {
      CHECK(row["status"] == "FAIL");
      CHECK(row["metrics"].is_null());
      CHECK(fs::exists(row["new_image"].get<std::string>()));
    }
}

TEST_CASE("golden: usage and input errors exit 2") {
  GoldenFixture fx("usage");
  auto run_cli_errors = [&](std::vector<std::string> extra) {
    try {
      return fx.run(std::move(extra));
    } catch (const cr::UsageError&) {
      return 2;  // the CLI turns these into exit code 2
    } catch (const cr::InputError&) {
      return 2;
    }
  };
  CHECK(run_cli_errors({"--only", "nothing*"}) == 2);
  CHECK(run_cli_errors({"--exact"}) == 2);
  CHECK(run_cli_errors({"--prune"}) == 2);
  CHECK(run_cli_errors({"--threads", "1"}) == 2);
  CHECK(run_cli_errors({"--resolution", "48x"}) == 2);
  CHECK(run_cli_errors({"--tolerances", fx.root.file("none.json")}) == 2);
  // Every threshold needs its reason.
  fx.write(fx.root.file("unexplained.json"),
           R"({"profiles": {"default": {"max_abs": 0.1, "rmse": 0.01, "pixel_threshold": 0.01,
               "max_fraction": 0.01, "flip_mean": 0.01, "why": {"max_abs": "x"}}}})");
  CHECK(run_cli_errors({"--tolerances", fx.root.file("unexplained.json")}) == 2);
  fs::remove_all(fx.profiles);
  CHECK(run_cli_errors({}) == 2);
  CHECK(fx.golden_files().size() == 1);  // only tolerances.json
}

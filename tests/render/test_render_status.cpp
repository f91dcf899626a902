// `cpurender render` leaves a report.json saying how far it got: "running"
// while frames render, "complete" at the end, "failed: <message>" with the
// frames on disk when a frame fails to render or to be written; the command
// still fails.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>

#include "engine/cli/commands.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

// What the probe plugin saw of report.json as each frame rendered, and the
// frame (counted from 0) at which it throws, if any.
struct Probe {
  std::string report_path;
  int throw_at = -1;
  std::vector<std::string> statuses;
};

class ProbePlugin : public cr::Plugin {
 public:
  explicit ProbePlugin(std::shared_ptr<Probe> probe) : probe_(std::move(probe)) {}
  std::string name() const override { return "probe"; }
  bool configure(const cr::Scene&, const cr::SceneDescription&, const cr::Profile&) override { return true; }
  void add_passes(cr::FrameGraph&, const cr::FrameContext&, cr::EngineResources&) override {}
  void report_frame(nlohmann::json&) override {
    const int frame = int(probe_->statuses.size());
    probe_->statuses.push_back(std::filesystem::exists(probe_->report_path)
                                   ? nlohmann::json::parse(cr::read_file_bytes(probe_->report_path))["status"]
                                   : "no report.json");
    if (frame == probe_->throw_at) throw cr::Error("probe: frame " + std::to_string(frame) + " went wrong");
  }

 private:
  std::shared_ptr<Probe> probe_;
};

struct RenderRun {
  ScratchDir dir;
  std::string out = dir.file("out");
  std::shared_ptr<Probe> probe = std::make_shared<Probe>();

  explicit RenderRun(const std::string& name) : dir(name) {
    std::filesystem::create_directories(out);
    std::ofstream(dir.file("tiny.json")) << R"({"resolution": [32, 24], "antialiasing": "none", "shadow_map_size": 0})";
    probe->report_path = out + "/report.json";
  }
  // The CLI's exit code for rendering `frames` frames of a small box.
  int render(int frames) {
    std::vector<std::string> args = {"cpurender", "render",
                                     std::string(CR_ASSIMP_GLTF_DIR) + "/BoxTextured-glTF/BoxTextured.gltf",
                                     "--profile", dir.file("tiny.json"), "--frames", std::to_string(frames),
                                     "--threads", "2", "--out", out, "--quiet"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    std::shared_ptr<Probe> shared = probe;
    return cr::run_cli(int(argv.size()), argv.data(), [shared](cr::PluginRegistry& registry, cr::CommandRegistry&, cr::ModuleTruthRegistry&) {
      registry.add("probe", [shared] { return std::make_unique<ProbePlugin>(shared); });
    });
  }
  nlohmann::json report() const { return nlohmann::json::parse(cr::read_file_bytes(out + "/report.json")); }
  bool exists(const std::string& name) const { return std::filesystem::exists(out + "/" + name); }
};

}  // namespace

TEST_CASE("render: report.json says running while frames render, complete at the end") {
  RenderRun run("render-status-complete");
  REQUIRE(run.render(2) == 0);
  CHECK(run.probe->statuses == std::vector<std::string>{"running", "running"});
  const nlohmann::json report = run.report();
  CHECK(report["status"] == "complete");
  CHECK(report["frames"].size() == 2);
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(run.out)) files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  CHECK(files == std::vector<std::string>{"frame_0000.png", "frame_0001.png", "report.json", "trace.json"});
}

TEST_CASE("render: a frame that cannot be written leaves failed: <error> with the frames before it") {
  RenderRun run("render-status-write");
  std::filesystem::create_directory(run.out + "/frame_0001.png");  // the second frame's file cannot replace it
  CHECK(run.render(3) == 2);
  const nlohmann::json report = run.report();
  const std::string status = report["status"];
  CHECK(status.rfind("failed: ", 0) == 0);
  CHECK(status.find("frame_0001.png: cannot replace file") != std::string::npos);
  REQUIRE(report["frames"].size() == 1);
  CHECK(report["frames"][0]["frame"] == 0);
  CHECK(run.exists("frame_0000.png"));
  CHECK_FALSE(run.exists("frame_0002.png"));
  CHECK_FALSE(run.exists("trace.json"));
}

TEST_CASE("render: a frame that throws while rendering leaves failed: <error> and fails the command") {
  RenderRun run("render-status-throw");
  run.probe->throw_at = 1;
  CHECK(run.render(3) == 2);
  const nlohmann::json report = run.report();
  CHECK(report["status"] == "failed: probe: frame 1 went wrong");
  CHECK(report["frames"].size() == 1);
  CHECK(run.exists("frame_0000.png"));
  CHECK_FALSE(run.exists("frame_0001.png"));
}

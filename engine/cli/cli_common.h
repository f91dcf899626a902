#pragma once
// What the render-like commands share: scene/profile/threads options, loading
// a run's inputs, converting frame records into reports, writing frames.
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "engine/cli/arg_parser.h"
#include "engine/core/memory_budget.h"
#include "engine/core/profile.h"
#include "engine/output/timing_report.h"
#include "engine/planning/auto_plan.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/plugin_registry.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"

namespace cr {

class ModuleTruthRegistry;

struct RunSetup {
  SceneDescription description;
  Profile profile;
  std::shared_ptr<Scene> scene;
  unsigned threads = 1;
  int frames = 1;
  // What the run was estimated to need before anything large was allocated:
  // frame buffers, shadow maps, decoded textures and buffers, plugin LUTs and grids.
  MemoryBudget memory;
  // Under --profile auto: what the planner chose and why (profile is its result).
  std::optional<AutoPlan> plan;
};

// What a run asks beyond its scene and profile.
struct RunRequest {
  double error_budget = 0.02;  // --profile auto: mean relative luminance error, a fraction (auto_plan.h)
  std::string plan_table;      // --profile auto: the planner's table; empty: auto_table_path()
  int frames = 0;              // the frames to be rendered; 0: the scene's
  // Changes to the scene description before anything is planned (the CLI's overrides).
  std::function<void(SceneDescription&)> adjust_description;
};

// "auto" or "auto:BASE" (BASE a profile name or file; default desktop).
bool is_auto_profile(const std::string& profile);
// The shipped table the planner reads (profiles/planner/auto_table.json next to the executable).
std::string auto_table_path();

// "WxH" with 1..16384 each; UsageError naming `command` otherwise.
std::pair<int, int> parse_resolution(const std::string& text, const std::string& command);
// --profile, --error-budget, --plan-table, --resolution, --frames, --threads, --memory-limit,
// --allow-missing-images, --allow-outside-paths and the scene overrides (scene_overrides.h: --camera,
// --sun, --sky, --exposure).
void add_scene_options(ArgParser& p);
// --allow-missing-images and --allow-outside-paths, for commands that load models.
void add_model_access_options(ArgParser& p);
// What those two flags allow.
GltfLoadOptions model_access(const ArgParser& p);
// Loads scene (positional 0 or the default scene), profile and glTF, applying overrides.
RunSetup load_run_setup(const ArgParser& p, const PluginRegistry& registry);
// --error-budget (a fraction in (0, 1)) and --plan-table.
RunRequest plan_options(const ArgParser& p);
// --threads N (1..1024), default: all hardware threads.
unsigned threads_option(const ArgParser& p);
// Loads the inputs of one run without a command line (benchmarks, golden tests).
// `model` says what the glTF may do (missing images, paths); its texture
// budget is the profile's. The run's memory estimate is checked against
// `memory_limit` (bytes, 0 = none) as each part is loaded: InputError naming
// the file and field that ask for too much. An "auto" profile is planned
// for the scene once it is loaded, from `plan` (the frame estimates follow).
RunSetup load_run(const std::string& scene_path, const std::string& profile, const PluginRegistry& registry,
                  int width, int height, unsigned threads, GltfLoadOptions model = {},
                  size_t memory_limit = MemoryBudget::default_limit(), const RunRequest& request = {});

// Runs the scene file's animation over the frames (animation.fps) on the
// renderer of `setup`'s scene; nothing for a still scene.
void attach_playback(Renderer& renderer, const RunSetup& setup);

RunReport make_run_report(const RunSetup& setup, const JobSystem& jobs);
FrameTiming to_report_frame(const FrameRecord& record);

// The resolved (exposed, tonemapped, sRGB) frame as an RGB8 PNG (atomic).
void write_frame_png(const std::string& path, const FrameBuffers& buffers);
// Linear radiance (half) + distance Z (float) EXR (atomic).
void write_frame_exr(const std::string& path, const FrameBuffers& buffers);

int render_command(const std::vector<std::string>& args, const PluginRegistry& registry);
int bench_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// Measures each point against the ground truths of `truths` too (--truth).
int sweep_command(const std::vector<std::string>& args, const PluginRegistry& registry,
                  const ModuleTruthRegistry& truths);
int antialiasing_command(const std::vector<std::string>& args, const PluginRegistry& registry);
int merge_command(const std::vector<std::string>& args);

}  // namespace cr

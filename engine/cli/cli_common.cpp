#include "engine/cli/cli_common.h"

#include <cstdlib>

#include "engine/cli/paths.h"
#include "engine/cli/scene_overrides.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/exr_io.h"
#include "engine/output/png_io.h"
#include "engine/render/frame_memory.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"

namespace cr {

void add_scene_options(ArgParser& p) {
  p.option("profile", "NAME|FILE", "render profile: a name in profiles/, a .json path, or auto[:BASE] (planned for the scene)", "desktop")
      .option("error-budget", "FRACTION", "--profile auto: the frame's error budget, mean relative luminance (0.02 = 2%)", "0.02")
      .option("plan-table", "FILE", "--profile auto: the table of measured options (default: profiles/planner/auto_table.json)")
      .option("resolution", "WxH", "override the profile's resolution, e.g. 640x360")
      .option("frames", "N", "number of frames (default: the scene's)")
      .option("threads", "N", "worker threads including the main thread (default: all cores)")
      .option("memory-limit", "SIZE",
              "refuse a run estimated to need more, e.g. 4G, 512M; 0: no limit (default: half the machine's memory, " +
                  MemoryBudget::format_bytes(MemoryBudget::default_limit()) + ")");
  add_model_access_options(p);
  add_scene_override_options(p);
}

void add_model_access_options(ArgParser& p) {
  p.flag("allow-missing-images", "render with factor-only materials where image files are missing")
      .flag("allow-outside-paths", "let a model's URIs name files outside its folder and subfolders");
}

GltfLoadOptions model_access(const ArgParser& p) {
  GltfLoadOptions o;
  o.allow_missing_images = p.has("allow-missing-images");
  o.allow_outside_paths = p.has("allow-outside-paths");
  return o;
}

std::pair<int, int> parse_resolution(const std::string& text, const std::string& command) {
  // Digits only, at most 5 of them each: no sign, no spaces, no overflow
  // (sscanf's %d wrapped 4294967360 to 64).
  const size_t x = text.find('x');
  auto side = [&](size_t begin, size_t end) {
    if (end <= begin || end - begin > 5) return 0;
    int v = 0;
    for (size_t i = begin; i < end; ++i) {
      if (text[i] < '0' || text[i] > '9') return 0;
      v = v * 10 + (text[i] - '0');
    }
    return v;
  };
  const int w = x == std::string::npos ? 0 : side(0, x), h = x == std::string::npos ? 0 : side(x + 1, text.size());
  if (w < 1 || h < 1 || w > 16384 || h > 16384)
    throw UsageError(command + ": --resolution expects WxH with 1..16384 each, got '" + text + "'");
  return {w, h};
}

bool is_auto_profile(const std::string& profile) { return profile == "auto" || profile.rfind("auto:", 0) == 0; }

std::string auto_table_path() { return executable_dir() + "/profiles/planner/auto_table.json"; }

RunSetup load_run(const std::string& scene_path, const std::string& profile, const PluginRegistry& registry,
                  int width, int height, unsigned threads, GltfLoadOptions model, size_t memory_limit,
                  const RunRequest& request) {
  RunSetup s;
  s.memory = MemoryBudget(memory_limit);
  const std::vector<std::string> sections = registry.names();
  const bool planned = is_auto_profile(profile);
  const std::string profile_path =
      resolve_profile_path(!planned ? profile : profile.size() > 5 ? profile.substr(5) : std::string("desktop"));
  // A planned profile starts from the base's document: read it once.
  nlohmann::json base_doc;
  if (planned) base_doc = load_json_file(profile_path);
  s.profile = planned ? parse_profile(base_doc, profile_path, sections) : load_profile(profile_path, sections);
  if (width > 0) {
    s.profile.width = width;
    s.profile.height = height;
  }
  s.description = load_scene_description(scene_path, sections, scene_asset_dirs());
  if (request.adjust_description) request.adjust_description(s.description);
  const std::vector<std::unique_ptr<Plugin>> plugins = registry.create_all();
  // Cheapest to know first: what the profile's frames and plugins need (for
  // a planned profile, once the plan exists: it needs the scene).
  auto estimate = [&] {
    estimate_frame_memory(s.profile, s.memory);
    for (const std::unique_ptr<Plugin>& plugin : plugins)
      if (plugin) plugin->estimate_memory(s.description, s.profile, s.memory);  // null: a section name only
  };
  if (!planned) estimate();
  model.texture_decode_budget = size_t(s.profile.texture_decode_budget_mb) << 20;
  model.memory = &s.memory;
  s.scene = std::make_shared<Scene>(load_gltf(s.description.gltf_path, model));
  pose_described_scene(*s.scene, s.description);  // the scene file's animation pose, else the rest pose
  s.threads = threads > 0 ? threads : JobSystem::default_thread_count();
  s.frames = request.frames > 0 ? request.frames : s.description.frames;
  if (planned) {
    if (width > 0) base_doc["resolution"] = {width, height};
    s.plan = plan_auto_profile(*s.scene, s.description, base_doc, s.profile, load_plan_table(request.plan_table.empty() ? auto_table_path() : request.plan_table),
                               plugins, request.error_budget, s.frames, s.profile.width, s.profile.height);
    s.profile = parse_profile(s.plan->profile, "auto (" + profile_path + ")", sections);
    estimate();
  }
  return s;
}

RunRequest plan_options(const ArgParser& p) {
  RunRequest r;
  const std::string text = p.get("error-budget");
  char* end = nullptr;
  r.error_budget = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(r.error_budget > 0.0) || !(r.error_budget < 1.0))
    throw UsageError("--error-budget expects a fraction in (0, 1), e.g. 0.02 for 2%, got '" + text + "'");
  if (p.has("plan-table")) r.plan_table = p.get("plan-table");
  return r;
}

unsigned threads_option(const ArgParser& p) {
  return p.has("threads") ? unsigned(p.get_int("threads", 1, 1024)) : JobSystem::default_thread_count();
}

RunSetup load_run_setup(const ArgParser& p, const PluginRegistry& registry) {
  int w = 0, h = 0;
  if (p.has("resolution")) std::tie(w, h) = parse_resolution(p.get("resolution"), "render");
  const unsigned threads = p.has("threads") ? unsigned(p.get_int("threads", 1, 1024)) : 0;
  size_t memory_limit = MemoryBudget::default_limit();
  if (p.has("memory-limit") && !MemoryBudget::parse_size(p.get("memory-limit"), memory_limit))
    throw UsageError("render: --memory-limit expects a size such as 4G, 512M, 100k or a byte count, got '" +
                     p.get("memory-limit") + "'");
  const std::string scene = p.positional().empty() ? default_scene_path() : p.positional()[0];
  const SceneOverrides overrides = parse_scene_overrides(p, "render");
  RunRequest request = plan_options(p);
  if (p.has("frames")) request.frames = p.get_int("frames", 1, 1000000);
  request.adjust_description = [&](SceneDescription& d) { apply_scene_overrides(overrides, d); };
  RunSetup s = load_run(scene, p.get("profile"), registry, w, h, threads, model_access(p), memory_limit, request);
  return s;
}

void attach_playback(Renderer& renderer, const RunSetup& setup) {
  const SceneDescription& d = setup.description;
  if (!d.animation || !d.animation->fps) return;
  const std::optional<size_t> animation = described_animation(*setup.scene, d);
  std::shared_ptr<Scene> scene = setup.scene;
  const AnimationSpec spec = *d.animation;
  renderer.play_animation([scene, animation, spec](int frame) {
    pose_scene(*scene, *scene->animation, animation, spec.time_at(frame));
  });
}

RunReport make_run_report(const RunSetup& setup, const JobSystem& jobs) {
  RunReport r;
  r.scene = setup.description.path;
  r.profile = setup.profile.path;
  r.width = setup.profile.width;
  r.height = setup.profile.height;
  r.threads = jobs.thread_count();
  r.frame_budget_ms = setup.profile.frame_budget_ms;
  r.build.compiler = compiler_description();
#ifdef NDEBUG
  r.build.build_type = "optimised (NDEBUG)";
#else
  r.build.build_type = "debug (assertions on)";
#endif
  r.build.flags = "-ffp-contract=off -fno-fast-math";
  r.extra["triangles"] = setup.scene->triangle_count();
  r.extra["draws"] = setup.scene->draws.size();
  r.extra["memory_estimate_bytes"] = setup.memory.total();
  r.extra["memory_limit_bytes"] = setup.memory.limit();
  if (setup.plan) r.extra["plan"] = setup.plan->to_json();
  if (setup.profile.scaled())  // the resolution above is the output's; the scene renders at this size
    r.extra["render_resolution"] = {{"width", setup.profile.render_width()}, {"height", setup.profile.render_height()}};
  return r;
}

FrameTiming to_report_frame(const FrameRecord& rec) {
  FrameTiming f = rec;
  f.plugins["raster"] = rec.raster;
  return f;
}

void write_frame_png(const std::string& path, const FrameBuffers& b) {
  Image8 img;
  img.width = b.width;
  img.height = b.height;
  img.channels = 3;
  img.data = b.display;
  write_png(path, img);
}

void write_frame_exr(const std::string& path, const FrameBuffers& b) {
  ExrImage img;
  img.color = ImageRGBf(b.width, b.height);
  for (size_t i = 0; i < b.color.size(); ++i)
    for (int c = 0; c < 3; ++c) img.color.rgb[i * 3 + c] = b.color[i][c];
  img.depth = b.distance;
  write_exr(path, img);
}

}  // namespace cr

#include "engine/cli/cli_common.h"


#include "engine/cli/paths.h"
#include "engine/cli/scene_overrides.h"
#include "engine/core/error.h"
#include "engine/output/exr_io.h"
#include "engine/output/png_io.h"
#include "engine/render/frame_memory.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"

namespace cr {

void add_scene_options(ArgParser& p) {
  p.option("profile", "NAME|FILE", "render profile: a name in profiles/ or a .json path", "desktop")
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

RunSetup load_run(const std::string& scene_path, const std::string& profile, const PluginRegistry& registry,
                  int width, int height, unsigned threads, GltfLoadOptions model, size_t memory_limit) {
  RunSetup s;
  s.memory = MemoryBudget(memory_limit);
  const std::vector<std::string> sections = registry.names();
  s.profile = load_profile(resolve_profile_path(profile), sections);
  if (width > 0) {
    s.profile.width = width;
    s.profile.height = height;
  }
  s.description = load_scene_description(scene_path, sections, scene_asset_dirs());
  // Cheapest to know first: what the profile's frames and plugins need.
  estimate_frame_memory(s.profile, s.memory);
  for (const std::unique_ptr<Plugin>& plugin : registry.create_all())
    if (plugin) plugin->estimate_memory(s.description, s.profile, s.memory);  // null: a section name only
  model.texture_decode_budget = size_t(s.profile.texture_decode_budget_mb) << 20;
  model.memory = &s.memory;
  s.scene = std::make_shared<Scene>(load_gltf(s.description.gltf_path, model));
  pose_described_scene(*s.scene, s.description);  // the scene file's animation pose, else the rest pose
  s.threads = threads > 0 ? threads : JobSystem::default_thread_count();
  s.frames = s.description.frames;
  return s;
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
  RunSetup s = load_run(scene, p.get("profile"), registry, w, h, threads, model_access(p), memory_limit);
  apply_scene_overrides(overrides, s.description);
  if (p.has("frames")) s.frames = p.get_int("frames", 1, 1000000);
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

#include "fog/tools/fog_command_common.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "engine/cli/cli_common.h"
#include "engine/cli/paths.h"
#include "engine/core/error.h"
#include "engine/core/luminance.h"
#include "engine/output/percentile.h"
#include "engine/render/composite_strips.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"

namespace cr {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void add_fog_command_options(ArgParser& p) {
  p.option("profile", "NAME|FILE", "render profile: a name in profiles/ or a .json path", "desktop")
      .option("resolution", "WxH", "override the profile's resolution")
      .option("threads", "N", "worker threads (default: all cores)");
}

FogRun load_fog_run(const ArgParser& args, const PluginRegistry& registry) {
  const std::vector<std::string> sections = registry.names();
  Profile profile = load_profile(resolve_profile_path(args.get("profile")), sections);
  if (args.has("resolution")) std::tie(profile.width, profile.height) = parse_resolution(args.get("resolution"), "fog");
  SceneDescription description = load_scene_description(args.positional().at(0), sections, scene_asset_dirs());
  GltfLoadOptions options;
  options.texture_decode_budget = size_t(profile.texture_decode_budget_mb) << 20;
  auto scene = std::make_shared<Scene>(load_gltf(description.gltf_path, options));
  pose_described_scene(*scene, description);  // the scene file's animation pose, else the rest pose
  return make_fog_run(std::move(description), std::move(profile), std::move(scene));
}

FogRun make_fog_run(SceneDescription description, Profile profile, std::shared_ptr<const Scene> scene) {
  FogRun run{std::move(description), std::move(profile), std::move(scene), {}, {}};
  // The tools composite the fog over the base renderer's output-size buffers.
  if (run.profile.scaled())
    throw InputError(run.profile.path, "render_scale: the fog tools measure at the output size; it must be 1");
  if (!run.description.plugins.contains("fog"))
    throw InputError(run.description.path, "has no \"fog\" section: nothing to measure");
  run.fog_scene = parse_fog_scene(run.description.plugins.at("fog"), run.description.path);
  if (run.profile.plugins.contains("fog"))
    run.fog_profile = parse_fog_profile(run.profile.plugins.at("fog"), run.profile.path);
  run.fog_profile = resolve_fog_settings(run.fog_profile, run.fog_scene);
  return run;
}

SceneDescription with_turning_sun(const SceneDescription& scene, const FrameView& first, int frames,
                                  double degrees_per_frame) {
  SceneDescription out = scene;
  const glm::vec3 s0 = first.sun_direction;
  const float azimuth = float(glm::degrees(std::atan2(double(s0.x), double(s0.z))));
  const float elevation = float(glm::degrees(std::asin(double(std::clamp(s0.y, -1.0f, 1.0f)))));
  if (out.sun.illuminance > 0.0f) out.sun.color = first.sun_illuminance / out.sun.illuminance;
  const int last = std::max(frames - 1, 1);
  out.sun.keys = {SunKey{0, azimuth, elevation},
                  SunKey{last, azimuth + float(degrees_per_frame) * float(last), elevation}};
  return out;
}

std::vector<std::unique_ptr<Plugin>> plugins_without_fog(const PluginRegistry& registry) {
  std::vector<std::unique_ptr<Plugin>> out;
  for (auto& p : registry.create_all())
    if (p->name() != "fog") out.push_back(std::move(p));
  return out;
}

std::vector<glm::vec3> froxel_frame(FroxelFog& fog, const FrameView& view, const Renderer& base, JobSystem& jobs,
                                    FroxelTimes* times) {
  FroxelTimes t;
  auto t0 = std::chrono::steady_clock::now();
  fog.begin_frame(view, jobs, &base.buffers().distance);
  fog.density();
  t.density = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.lighting(base.shadow_map(), jobs, &base.previous_shadow_map());
  t.lighting = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.reproject(jobs);
  t.reproject = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.filter(jobs);
  t.filter = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.integrate(base.light_environment(), jobs);
  t.integrate = ms_since(t0);
  FrameBuffers b = base.buffers();
  t0 = std::chrono::steady_clock::now();
  // Split as the engine's composite pass splits it.
  for_each_composite_strip(jobs, "fog.composite", b.width, b.height,
                           [&](int x0, int y0, int x1, int y1) { fog.composite(b, x0, y0, x1, y1); });
  t.composite = ms_since(t0);
  if (times) *times = t;
  return b.color;
}

ImageError relative_luminance_error(const std::vector<glm::vec3>& reference, const std::vector<glm::vec3>& test) {
  auto lum = [](const glm::vec3& c) { return luminance(glm::dvec3(c)); };  // in double
  std::vector<double> e(reference.size());
  double sum = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) {
    const double r = lum(reference[i]);
    e[i] = std::abs(lum(test[i]) - r) / std::max(r, 1e-6);
    sum += e[i];
  }
  ImageError out;
  out.mean = reference.empty() ? 0.0 : sum / double(reference.size());
  out.p95 = percentile_nearest_rank(std::move(e), 95.0);
  return out;
}

}  // namespace cr

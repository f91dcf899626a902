// fog-temporal: what reprojection costs and buys, per test path.
//   fast path    the scene's first camera translated `speed` m and yawed `turn`
//                degrees per frame; ghosting = mean relative luminance error
//                against the converged (7 jitter samples, no history) frame
//   moving sun   the first camera held still while the sun's azimuth turns
//                `sun-turn` degrees per frame, so the light shafts sweep
//                through history that holds where they were; same ghosting
//   static view  the first camera held still; temporal noise = mean relative
//                luminance change between consecutive frames, plus the error
//                against the converged frame
// Each with the profile's reprojection (clamped history, light-change
// rejection, still-view accumulation), the same blind to light changes,
// HDRP's unclamped fixed-weight history and no reprojection (single jittered
// sample per frame).
#include <cmath>
#include <cstdio>

#include "engine/core/error.h"
#include "engine/render/frame_view.h"
#include "engine/cli/cli_common.h"
#include "fog/tools/fog_command_common.h"
#include "fog/tools/fog_commands.h"

namespace cr {

namespace {

struct Variant {
  const char* name;
  FogProfileSettings profile;
};

std::vector<Variant> variants(const FogProfileSettings& p) {
  FogProfileSettings clamped = p, unaware = p, hdrp = p, single = p;
  clamped.reprojection = unaware.reprojection = hdrp.reprojection = true;
  clamped.history_clamp = unaware.history_clamp = true;
  clamped.light_change_rejection = true;
  unaware.light_change_rejection = hdrp.light_change_rejection = false;
  hdrp.history_clamp = false;
  hdrp.still_accumulation = false;  // HDRP blends with one fixed weight
  single.reprojection = false;
  return {{"reprojection (clamped)", clamped},
          {"clamped, light-blind", unaware},
          {"reprojection (HDRP)", hdrp},
          {"no reprojection", single}};
}

// The seven jitter samples averaged in one frame, no history; `filter`: with the 3x3 filter.
std::vector<glm::vec3> converged(const FogRun& run, const FrameView& view, const Renderer& base, JobSystem& jobs,
                                 bool filter) {
  FogProfileSettings p = run.fog_profile;
  p.reprojection = false;
  p.filter = filter;
  FroxelFog fog(p, run.fog_scene);
  fog.set_lighting_samples(7);
  FrameView v = view;
  v.history_valid = false;
  return froxel_frame(fog, v, base, jobs, nullptr);
}

struct PathError {
  std::vector<double> mean, worst;  // per variant, over frames >= 8
};

// Ghosting of each variant along a path (a scene description whose camera or
// sun keys move per frame): the error against the converged frame.
PathError path_error(const FogRun& run, const SceneDescription& path, int frames, const std::vector<Variant>& vs,
                     const PluginRegistry& registry, JobSystem& jobs) {
  PathError out{std::vector<double>(vs.size(), 0.0), std::vector<double>(vs.size(), 0.0)};
  Renderer base(*run.scene, path, run.profile, plugins_without_fog(registry), jobs);
  std::vector<FroxelFog> fogs;
  for (const Variant& v : vs) fogs.emplace_back(v.profile, run.fog_scene);
  for (int f = 0; f < frames; ++f) {
    base.render_frame(f);
    const FrameView view = base.frame_view(f);
    const std::vector<glm::vec3> truth = converged(run, view, base, jobs, run.fog_profile.filter);
    for (size_t i = 0; i < vs.size(); ++i) {
      const double e = relative_luminance_error(truth, froxel_frame(fogs[i], view, base, jobs, nullptr)).mean;
      if (f < 8) continue;
      out.mean[i] += e / double(frames - 8);
      out.worst[i] = std::max(out.worst[i], e);
    }
  }
  return out;
}

void print_path(const char* title, const PathError& e, const std::vector<Variant>& vs) {
  std::printf("%s: error vs converged frame\n", title);
  std::printf("  %-26s %10s %10s\n", "", "mean", "worst");
  for (size_t i = 0; i < vs.size(); ++i) std::printf("  %-26s %10.4f %10.4f\n", vs[i].name, e.mean[i], e.worst[i]);
}

}  // namespace

int fog_temporal_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser a("fog-temporal", "cpurender fog-temporal SCENE [options]",
              "Ghosting on a fast camera path and under a moving sun, and temporal noise with a static\n"
              "camera, with and without reprojection (statistics over frames >= 8).");
  add_fog_command_options(a);
  a.option("frames", "N", "frames per path (>= 9)", "24")
      .option("speed", "M", "metres the fast camera moves per frame", "1.5")
      .option("turn", "DEG", "degrees the fast camera turns per frame", "3")
      .option("sun-turn", "DEG", "degrees the sun's azimuth turns per frame on the moving-sun path", "2");
  if (!a.parse(args, 1, 1)) return 0;
  const FogRun run = load_fog_run(a, registry);
  JobSystem jobs(threads_option(a));
  const int frames = a.get_int("frames", 9, 10000);
  const double speed = a.get_double("speed", 0.0, 1e4);
  const double turn = a.get_double("turn", -180.0, 180.0);
  const double sun_turn = a.get_double("sun-turn", -180.0, 180.0);
  const std::vector<Variant> vs = variants(run.fog_profile);
  std::printf("fog-temporal %s, %dx%d, %d frames (statistics over frames >= 8)\n", run.description.path.c_str(),
              run.profile.width, run.profile.height, frames);

  // Fast path: explicit camera keys replace the scene's camera.
  const FrameView view0 = make_frame_view(*run.scene, run.description, 0, run.profile.width, run.profile.height);
  const Camera c0 = view0.camera;
  SceneDescription fast = run.description;
  fast.camera.gltf_camera.reset();
  fast.camera.keys.clear();
  fast.camera.znear = c0.znear;
  for (int f = 0; f < frames; ++f) {
    const double yaw = glm::radians(turn * f);
    const glm::dvec3 fw(c0.forward), right(c0.right), up(0.0, 1.0, 0.0);
    // Rotate forward about world up by yaw (Rodrigues).
    const glm::dvec3 dir = fw * std::cos(yaw) + glm::cross(up, fw) * std::sin(yaw) + up * glm::dot(up, fw) * (1.0 - std::cos(yaw));
    CameraKey k;
    k.frame = f;
    k.position = c0.position + right * (speed * f);
    k.target = k.position + dir * 10.0;
    k.vfov_deg = float(glm::degrees(double(c0.vfov_rad)));
    fast.camera.keys.push_back(k);
  }
  char title[128];
  std::snprintf(title, sizeof title, "fast path (%.2f m + %.2f deg per frame)", speed, turn);
  print_path(title, path_error(run, fast, frames, vs, registry, jobs), vs);

  // Moving sun: the first camera held (one key), the sun turning.
  SceneDescription moving = with_turning_sun(run.description, view0, frames, sun_turn);
  moving.camera.gltf_camera.reset();
  moving.camera.znear = c0.znear;
  CameraKey still;
  still.position = c0.position;
  still.target = c0.position + glm::dvec3(c0.forward) * 10.0;
  still.vfov_deg = float(glm::degrees(double(c0.vfov_rad)));
  moving.camera.keys = {still};
  std::snprintf(title, sizeof title, "moving sun (azimuth %.2f deg per frame, elevation %.1f deg)", sun_turn,
                double(moving.sun.keys.front().elevation_deg));
  print_path(title, path_error(run, moving, frames, vs, registry, jobs), vs);

  // Static view.
  Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(registry), jobs);
  base.render_frame(0);
  // Each variant against what it converges to: a still view with still
  // accumulation drops the filter.
  const std::vector<glm::vec3> filtered = converged(run, view0, base, jobs, true);
  const std::vector<glm::vec3> unfiltered = converged(run, view0, base, jobs, false);
  std::printf("static view: temporal noise (frame-to-frame change) and error vs converged frame\n");
  std::printf("  %-26s %10s %10s\n", "", "noise", "error");
  for (const Variant& v : vs) {
    const bool filters = v.profile.filter && !(v.profile.reprojection && v.profile.still_accumulation);
    const std::vector<glm::vec3>& truth = filters ? filtered : unfiltered;
    FroxelFog fog(v.profile, run.fog_scene);
    std::vector<glm::vec3> prev;
    double noise = 0.0, error = 0.0;
    for (int f = 0; f < frames; ++f) {
      FrameView view = view0;
      view.frame = f;
      view.history_valid = f > 0;
      std::vector<glm::vec3> img = froxel_frame(fog, view, base, jobs, nullptr);
      if (f >= 8) {
        noise += relative_luminance_error(prev, img).mean / double(frames - 8);
        error += relative_luminance_error(truth, img).mean / double(frames - 8);
      }
      prev = std::move(img);
    }
    std::printf("  %-26s %10.4f %10.4f\n", v.name, noise, error);
  }
  return 0;
}

}  // namespace cr

// fog-accuracy: the froxel fog against the per-pixel ray-marched reference on
// one frame of a scene, for three froxel configurations:
//   temporal     the profile's grid after `warmup` frames of history (static view)
//   single       the same grid, one frame, no reprojection
//   2x non-temp  twice the resolution in x, y and z, no jitter, no reprojection
// Each line: grid, fog pass time, composite time, mean and p95 relative
// luminance error of the final image; then the reference's time.
#include <chrono>
#include <cstdio>

#include "engine/core/error.h"
#include "fog/fog_command_common.h"
#include "fog/fog_commands.h"
#include "fog/fog_reference.h"

namespace cr {

int fog_accuracy_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser a("fog-accuracy", "cpurender fog-accuracy SCENE [options]",
              "Froxel fog vs the per-pixel ray-marched reference on one frame: temporal grid, single frame,\n"
              "2x resolution; mean and p95 relative luminance error and the time of each.");
  add_fog_command_options(a);
  a.option("frame", "N", "frame of the scene to measure", "0")
      .option("samples", "N", "reference samples per pixel", "512")
      .option("warmup", "N", "history frames before the temporal measurement", "14");
  if (!a.parse(args, 1, 1)) return 0;
  const FogRun run = load_fog_run(a, registry);
  JobSystem jobs(fog_command_threads(a));
  const int frame = a.get_int("frame", 0, 1000000);
  const int samples = a.get_int("samples", 1, 65536);
  const int warmup = a.get_int("warmup", 0, 1000);

  Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(registry), jobs);
  base.render_frame(frame);
  const FrameView view = base.frame_view(frame);
  const int w = base.buffers().width, h = base.buffers().height;

  const auto t0 = std::chrono::steady_clock::now();
  const FogReferenceImage ref = render_fog_reference(run.fog_scene, run.fog_profile.fog_distance, view.camera, w, h,
                                                     base.light_environment(), base.shadow_map(),
                                                     base.buffers().distance, samples, jobs);
  const double ref_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::vector<glm::vec3> reference = base.buffers().color;
  for (size_t i = 0; i < reference.size(); ++i)
    reference[i] = reference[i] * ref.transmittance[i] + ref.in_scatter[i];

  struct Config {
    const char* name;
    FogProfileSettings profile;
    int frames;
  };
  FogProfileSettings single = run.fog_profile;
  single.reprojection = false;
  FogProfileSettings fine = single;
  fine.jitter = false;
  fine.froxel_size_px = std::max(1, run.fog_profile.froxel_size_px / 2);
  fine.slices = run.fog_profile.slices * 2;
  const Config configs[] = {{"temporal", run.fog_profile, run.fog_profile.reprojection ? warmup + 1 : 1},
                            {"single", single, 1},
                            {"2x non-temporal", fine, 1}};

  std::printf("fog-accuracy %s frame %d, %dx%d, %u threads, reference %d samples/pixel\n", run.description.path.c_str(),
              frame, w, h, jobs.thread_count(), samples);
  std::printf("%-16s %-12s %10s %12s %10s %10s\n", "config", "froxels", "passes ms", "composite ms", "mean err",
              "p95 err");
  for (const Config& c : configs) {
    FroxelFog fog(c.profile, run.fog_scene);
    FroxelTimes times;
    std::vector<glm::vec3> image;
    for (int i = 0; i < c.frames; ++i) {
      FrameView v = view;
      v.frame = frame + i;  // a static view: only the jitter sequence advances
      v.prev_camera = v.camera;
      v.history_valid = i > 0;
      image = froxel_frame(fog, v, base, jobs, &times);
    }
    const ImageError e = relative_luminance_error(reference, image);
    const FroxelGrid& g = fog.grid();
    const std::string dims = std::to_string(g.nx()) + "x" + std::to_string(g.ny()) + "x" + std::to_string(g.nz());
    std::printf("%-16s %-12s %10.2f %12.2f %10.4f %10.4f\n", c.name, dims.c_str(), times.passes(), times.composite,
                e.mean, e.p95);
  }
  std::printf("%-16s %-12s %10.1f\n", "reference", "per pixel", ref_ms);
  return 0;
}

}  // namespace cr

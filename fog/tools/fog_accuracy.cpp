#include "fog/tools/fog_accuracy.h"

#include <algorithm>
#include <chrono>

#include "fog/tools/fog_reference.h"

namespace cr {

FogAccuracy measure_fog_accuracy(const FogRun& run, const PluginRegistry& registry, JobSystem& jobs, int frame,
                                 int samples, int warmup) {
  Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(registry), jobs);
  base.render_frame(frame);
  const FrameView view = base.frame_view(frame);
  const int w = base.buffers().width, h = base.buffers().height;

  const auto t0 = std::chrono::steady_clock::now();
  const FogReferenceImage ref = render_fog_reference(run.fog_scene, run.fog_profile.fog_distance, view.camera, w, h,
                                                     base.light_environment(), base.shadow_map(),
                                                     base.buffers().distance, samples, jobs);
  FogAccuracy out;
  out.width = w;
  out.height = h;
  out.reference_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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

  auto measure = [&](const Config& c, std::vector<glm::vec3>& image) {
    FroxelFog fog(c.profile, run.fog_scene);
    FroxelTimes times;
    for (int i = 0; i < c.frames; ++i) {
      FrameView v = view;
      v.frame = frame + i;  // a static view: only the jitter sequence advances
      v.prev_camera = v.camera;
      v.history_valid = i > 0;
      image = froxel_frame(fog, v, base, jobs, &times);
    }
    const FroxelGrid& g = fog.grid();
    return FogAccuracyRow{c.name, g.nx(), g.ny(), g.nz(), times.passes(), times.composite,
                          relative_luminance_error(reference, image)};
  };
  std::vector<glm::vec3> temporal;
  for (const Config& c : configs) {
    std::vector<glm::vec3> image;
    out.rows.push_back(measure(c, image));
    if (&c == &configs[0]) temporal = std::move(image);
  }
  if (run.fog_profile.precision == FogPrecision::Fixed) {
    Config in_float = configs[0];
    in_float.name = "temporal, float";
    in_float.profile.precision = FogPrecision::Float;
    std::vector<glm::vec3> image;
    out.float_temporal = measure(in_float, image);
    out.fixed_against_float = relative_luminance_error(image, temporal);
  }
  return out;
}

}  // namespace cr

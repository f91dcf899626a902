#include "fog/tools/fog_accuracy.h"

#include <algorithm>
#include <chrono>

namespace cr {

FogReferenceImage render_fog_reference(const FogRun& run, const Renderer& base, const FrameView& view, int samples,
                                       JobSystem& jobs) {
  return render_fog_reference(run.fog_scene, run.fog_profile.fog_distance, view.camera, base.buffers().width,
                              base.buffers().height, base.light_environment(), base.shadow_map(),
                              base.buffers().distance, samples, jobs);
}

std::vector<glm::vec3> fog_reference_composite(const Renderer& base, const FogReferenceImage& ref) {
  std::vector<glm::vec3> image = base.buffers().color;
  for (size_t i = 0; i < image.size(); ++i) image[i] = image[i] * ref.transmittance[i] + ref.in_scatter[i];
  return image;
}

FroxelConfig temporal_config(const FogProfileSettings& profile, int warmup) {
  return {"temporal", profile, profile.reprojection ? warmup + 1 : 1};
}

FogAccuracyRow measure_froxel_config(const FogRun& run, const Renderer& base, const FrameView& view, JobSystem& jobs,
                                     const FroxelConfig& config, const std::vector<glm::vec3>& reference,
                                     std::vector<glm::vec3>& image) {
  FroxelFog fog(config.profile, run.fog_scene);
  FroxelTimes times;
  for (int i = 0; i < config.frames; ++i) {
    FrameView v = view;
    v.frame = view.frame + i;  // a static view: only the jitter sequence advances
    v.prev_camera = v.camera;
    v.history_valid = i > 0;
    image = froxel_frame(fog, v, base, jobs, &times);
  }
  const FroxelGrid& g = fog.grid();
  return FogAccuracyRow{config.name, g.nx(), g.ny(), g.nz(), times.passes(), times.composite,
                        relative_luminance_error(reference, image)};
}

FogAccuracy measure_fog_accuracy(const FogRun& run, const PluginRegistry& registry, JobSystem& jobs, int frame,
                                 int samples, int warmup) {
  Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(registry), jobs);
  base.render_frame(frame);
  const FrameView view = base.frame_view(frame);

  const auto t0 = std::chrono::steady_clock::now();
  const FogReferenceImage ref = render_fog_reference(run, base, view, samples, jobs);
  FogAccuracy out;
  out.width = base.buffers().width;
  out.height = base.buffers().height;
  out.reference_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<glm::vec3> reference = fog_reference_composite(base, ref);

  FogProfileSettings single = run.fog_profile;
  single.reprojection = false;
  FogProfileSettings fine = single;
  fine.jitter = false;
  fine.froxel_size_px = std::max(1, run.fog_profile.froxel_size_px / 2);
  fine.slices = run.fog_profile.slices * 2;
  const FroxelConfig configs[] = {temporal_config(run.fog_profile, warmup), {"single", single, 1},
                                  {"2x non-temporal", fine, 1}};
  std::vector<glm::vec3> temporal;
  for (const FroxelConfig& c : configs) {
    std::vector<glm::vec3> image;
    out.rows.push_back(measure_froxel_config(run, base, view, jobs, c, reference, image));
    if (&c == &configs[0]) temporal = std::move(image);
  }
  if (run.fog_profile.precision == FogPrecision::Fixed) {
    FroxelConfig in_float = configs[0];
    in_float.name = "temporal, float";
    in_float.profile.precision = FogPrecision::Float;
    std::vector<glm::vec3> image;
    out.float_temporal = measure_froxel_config(run, base, view, jobs, in_float, reference, image);
    out.fixed_against_float = relative_luminance_error(image, temporal);
  }
  return out;
}

}  // namespace cr

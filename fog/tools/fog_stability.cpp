#include "fog/tools/fog_stability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <vector>

#include "engine/output/stability_map.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/plugin.h"
#include "fog/froxel_fog.h"
#include "fog/tools/fog_reference.h"
#include "fog/tools/synthetic_fog_view.h"

namespace cr {

namespace {

// The sun low and to the side, so the wall's shadow is a shaft across the view.
const glm::vec3 kSun(0.8f, 0.35f, 0.2f);
constexpr float kSunLux = 1e5f, kAmbient = 1e3f;
const glm::vec3 kBackground(3000.0f);  // the sky behind the fog (cd/m^2)

double stability_ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Frame f of `frames`: 2 m up, 20 m in front of the wall, looking along -z, moving `speed` m along x per
// frame; every speed ends at the same view, so the last frames of all cells are measured against one reference.
Camera camera_at_frame(int f, int frames, float speed, int w, int h) {
  const glm::dvec3 pos(-3.0 - double(speed) * (frames - 1 - f), 2.0, 20.0);
  return Camera::look_at(pos, pos + glm::dvec3(0.3, 0.05, -1.0), glm::radians(60.0f), float(w) / float(h), 0.1f);
}

size_t non_finite_volume(const FroxelFog& fog) {
  size_t n = 0;
  const FroxelGrid& g = fog.grid();
  for (size_t column = 0; column < g.columns(); ++column)
    for (int k = 0; k < fog.view().active_slices[column]; ++k) {
      const IntegratedFroxel f = fog.integrated_froxel(column * size_t(g.nz()) + size_t(k));
      n += count_non_finite(std::span<const glm::vec3>(&f.in_scatter, 1)) + (std::isfinite(f.transmittance) ? 0 : 1);
    }
  return n;
}

std::vector<glm::vec3> composited(const FogReferenceImage& r) {
  std::vector<glm::vec3> out(r.in_scatter.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = kBackground * r.transmittance[i] + r.in_scatter[i];
  return out;
}

}  // namespace

FogStabilityCell evaluate_fog_stability(const FogStabilityCase& c, const FogStabilityOptions& options,
                                        JobSystem& jobs) {
  const int w = options.width, h = options.height;
  FogProfileSettings profile;
  profile.reprojection = c.reprojection;
  profile.history_weight = c.history_weight;
  profile.froxel_size_px = c.froxel_size_px;
  FogSceneSettings scene;
  scene.height_fog = true;
  scene.base_height = 1e4f;  // everything below the base: uniform density
  scene.max_height = 2e4f;
  scene.extinction = c.extinction;
  scene.albedo = glm::vec3(0.9f);
  scene.anisotropy = c.anisotropy;
  const LightEnvironment light = synthetic_light(kSun, kSunLux, kAmbient);
  const std::vector<float> distance(size_t(w) * h, INFINITY);  // sky everywhere: the whole fog range

  FogStabilityCell cell;
  FroxelFog fog(profile, scene);
  FrameBuffers buffers;
  buffers.resize(w, h);
  Camera camera, previous;
  ShadowMap shadow;
  int with_history = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < c.frames; ++f) {
    previous = camera;
    camera = camera_at_frame(f, c.frames, c.speed, w, h);
    FrameView view;
    view.frame = f;
    view.width = w;
    view.height = h;
    view.camera = camera;
    view.prev_camera = f > 0 ? previous : camera;
    view.history_valid = f > 0;
    shadow = wall_shadow_map(camera, kSun);
    fog.render(view, light, shadow, jobs, &distance);
    buffers.distance = distance;
    std::fill(buffers.color.begin(), buffers.color.end(), kBackground);
    fog.composite(buffers, 0, 0, w, h);
    cell.non_finite += non_finite_volume(fog) + count_non_finite(buffers.color);
    const FroxelFogStats& s = fog.stats();
    if (s.history_used && s.reproject.reads > 0) {
      cell.history_rejected += double(s.reproject.rejected) / double(s.reproject.reads);
      cell.history_clamped += double(s.reproject.clamped) / double(s.reproject.reads);
      cell.history_read += double(s.reproject.reads) / double(s.lit_froxels);
      ++with_history;
    }
  }
  cell.passes_ms = stability_ms_since(t0) / double(c.frames);
  if (with_history > 0) {
    cell.history_rejected /= with_history;
    cell.history_clamped /= with_history;
    cell.history_read /= with_history;
  }
  if (!options.reference) return cell;

  const auto r0 = std::chrono::steady_clock::now();
  auto reference = [&](int samples) {
    return render_fog_reference(scene, profile.fog_distance, camera, w, h, light, shadow, distance, samples, jobs);
  };
  const FogReferenceImage ref = reference(options.samples);
  cell.ref_ms = stability_ms_since(r0);
  const FogReferenceImage coarse = reference(std::max(1, options.samples / 2));
  const std::vector<glm::vec3> truth = composited(ref);
  cell.non_finite_reference = count_non_finite(truth);
  cell.error = relative_luminance_error(truth, buffers.color);
  cell.noise = relative_luminance_error(truth, composited(coarse));
  return cell;
}

}  // namespace cr

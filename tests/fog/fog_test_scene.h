#pragma once
// Small synthetic fog setups shared by the fog tests: a camera, a frame view,
// light and an optional shadow map with a wall casting a shaft edge.
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/luminance.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/plugin.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"
#include "engine/shading/sh_lighting.h"
#include "fog/froxel_fog.h"
#include "fog/tools/synthetic_fog_view.h"

namespace cr::fog_test {

inline Camera camera_at(const glm::dvec3& pos, const glm::dvec3& target, int w, int h, float vfov_deg = 60.0f) {
  return Camera::look_at(pos, target, glm::radians(vfov_deg), float(w) / float(h), 0.1f);
}

inline FrameView frame_view(const Camera& cam, const Camera& prev, int frame, bool history_valid, int w, int h) {
  FrameView v;
  v.frame = frame;
  v.width = w;
  v.height = h;
  v.camera = cam;
  v.prev_camera = prev;
  v.history_valid = history_valid;
  return v;
}

inline LightEnvironment light(const glm::vec3& sun_dir, float sun_lux, float ambient) {
  return synthetic_light(sun_dir, sun_lux, ambient);
}

// Shadow map over the region around the origin with a tall thin wall at
// x in [-1, 1] (all z), so the fog behind it (away from the sun) is in shadow.
inline ShadowMap wall_shadow(const Camera& cam, const glm::vec3& sun_dir, float wall_height = 40.0f) {
  return wall_shadow_map(cam, sun_dir, wall_height);
}

inline FogSceneSettings uniform_fog(float extinction, const glm::vec3& albedo, float g = 0.0f) {
  FogSceneSettings s;
  s.height_fog = true;
  s.base_height = 1e4f;  // everything below the base: constant density
  s.max_height = 2e4f;
  s.extinction = extinction;
  s.albedo = albedo;
  s.anisotropy = g;
  return s;
}

// Height fog (up to 20 m) and one noisy box volume in front of the cameras
// at (x, 2, 10) looking down -z: a density with structure along and across
// the columns.
inline FogSceneSettings noisy_volume_fog() {
  FogSceneSettings s = uniform_fog(0.03f, glm::vec3(0.9f), 0.4f);
  s.base_height = 0.0f;
  s.max_height = 20.0f;
  FogVolume v;
  v.center = {0, 2, -15};
  v.half_size = {4, 3, 5};
  v.extinction = 0.5f;
  v.fade = 1.0f;
  v.noise.enabled = true;
  s.volumes.push_back(v);
  return s;
}

// Renders the froxel volume for one frame (depth-culled by the same per-pixel
// distances, as the plugin does, unless `cull` is false) and composites it
// over `base` colour. previous_shadow: last frame's map, as the renderer gives it.
inline std::vector<glm::vec3> composite(FroxelFog& fog, const FrameView& view, const LightEnvironment& light,
                                        const ShadowMap& shadow, JobSystem& jobs,
                                        const std::vector<float>& distance, const glm::vec3& base,
                                        bool cull = true, const ShadowMap* previous_shadow = nullptr) {
  fog.render(view, light, shadow, jobs, cull ? &distance : nullptr, previous_shadow);
  FrameBuffers b;
  b.resize(view.width, view.height);
  b.distance = distance;
  for (glm::vec3& c : b.color) c = base;
  fog.composite(b, 0, 0, view.width, view.height);
  return b.color;
}

// Mean relative luminance difference of b against a.
inline double mean_relative_error(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double la = luminance(a[i]), lb = luminance(b[i]);
    sum += std::abs(lb - la) / std::max(la, 1e-6);
  }
  return sum / double(a.size());
}

}  // namespace cr::fog_test

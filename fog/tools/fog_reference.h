#pragma once
// Ground truth for the froxel fog: per-pixel, full-resolution ray marching of
// the same medium (FogMedium) and lighting (sun with the engine's
// ShadowMap::visibility and per-point sun illuminance, phase-convolved SH
// ambient) over the same range [near, min(distance, near + fog_distance)],
// with many samples, no froxels, no jitter and no history. Each of `samples`
// equal segments takes the medium and light at its midpoint and is integrated
// in closed form (homogeneous segment).
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"
#include "engine/scene/camera.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"
#include "fog/fog_settings.h"

namespace cr {

struct FogReferenceImage {
  int width = 0, height = 0;
  std::vector<glm::vec3> in_scatter;
  std::vector<float> transmittance;
};

FogReferenceImage render_fog_reference(const FogSceneSettings& scene, float fog_distance, const Camera& camera,
                                       int width, int height, const LightEnvironment& light,
                                       const ShadowMap& shadow, const std::vector<float>& distance, int samples,
                                       JobSystem& jobs);

}  // namespace cr

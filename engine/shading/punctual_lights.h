#pragma once
// Point and spot lights (KHR_lights_punctual) on a batch of shading points,
// through the same glTF BRDF as the sun. Illuminance on a surface facing a
// light at distance d: intensity (cd) * range window / d^2, times the cone
// attenuation for spots, as the extension recommends:
//   range window = clamp(1 - (d / range)^4, 0, 1)   (1 without a range)
//   cone         = clamp(cos(angle to the spot's axis) * scale + offset, 0, 1)^2,
//                  scale = 1 / max(0.001, cos(inner) - cos(outer)),
//                  offset = -cos(outer) * scale
// Punctual lights cast no shadows: the shadow map is the sun's alone.
#include <cstddef>

#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/shading/brdf.h"
#include "engine/shading/shading_batch.h"

namespace cr {

// A light in the form the lighting loop reads, prepared once per frame.
struct PunctualLightTerms {
  glm::vec3 position{0.0f};       // world space
  glm::vec3 intensity{0.0f};      // colour * candela
  float inv_range = 0.0f;         // 1 / range; 0: unlimited
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit: where a spot shines
  float cone_scale = 0.0f;        // point lights: scale 0, offset 1 (no cone)
  float cone_offset = 1.0f;
};
PunctualLightTerms punctual_light_terms(const PunctualLight& light);

// The range window at distance d (inv_range = 1 / range, 0 for none).
inline float range_window(float distance, float inv_range) {
  const float q = distance * inv_range;
  const float q2 = q * q;
  return clamp_nan_safe(1.0f - q2 * q2, 0.0f, 1.0f);
}

// The cone attenuation at cos_angle, the cosine between the spot's axis and
// the direction from the light to the point.
inline float cone_attenuation(float cos_angle, float scale, float offset) {
  const float a = clamp_nan_safe(cos_angle * scale + offset, 0.0f, 1.0f);
  return a * a;
}

// Adds the light reflected from each of `lights` towards the viewer to the
// batch's out_r/g/b (v*: unit view vectors; normals, base colour, metallic
// and roughness as SurfaceShader::shade_batch leaves them). Every component
// stays finite.
void add_punctual_lights(ShadingBatch& batch, const PunctualLightTerms* lights, size_t count, const float* vx,
                         const float* vy, const float* vz);

}  // namespace cr

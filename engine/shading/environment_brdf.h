#pragma once
// Directional albedo of the specular lobe under uniform lighting, split as
// f0 * A + B (the "split sum" environment BRDF), by Karis' analytic fit for
// mobile ("Physically Based Shading on Mobile", Unreal Engine blog, 2014)
// instead of a 2D lookup table. Used for the ambient specular term and to
// take the specularly reflected share away from the ambient diffuse term.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "engine/core/exp2_poly.h"

namespace cr {

struct EnvironmentBrdf {
  float a = 1.0f;  // scale of f0
  float b = 0.0f;  // bias
  glm::vec3 albedo(const glm::vec3& f0) const { return f0 * a + b; }
};

// roughness: perceptual, in [0, 1]; n_dot_v: cosine of the view angle.
inline EnvironmentBrdf environment_brdf(float roughness, float n_dot_v) {
  const glm::vec4 r = roughness * glm::vec4(-1.0f, -0.0275f, -0.572f, 0.022f) + glm::vec4(1.0f, 0.0425f, 1.04f, -0.04f);
  const float a004 = std::min(r.x * r.x, exp2_poly(-9.28f * std::max(n_dot_v, 0.0f))) * r.x + r.y;
  return {-1.04f * a004 + r.z, 1.04f * a004 + r.w};
}

}  // namespace cr

#pragma once
// Deterministic GGX importance sampling shared by the split-sum tables (the
// DFG table, the prefiltered environment): a Hammersley point set and the
// half vector GGX's D(h) (h.n) distributes (Walter et al. 2007), in the
// local frame where n = +Z; and an orthonormal frame around a unit vector.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/core/math_constants.h"

namespace cr {

// Point i of an n-point Hammersley set in [0, 1)^2: (i / n, radical inverse base 2 of i).
inline glm::vec2 hammersley(uint32_t i, uint32_t n) {
  uint32_t b = i;
  b = (b << 16) | (b >> 16);
  b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
  b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
  b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
  b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
  return {float(i) / float(n), float(double(b) * 0x1p-32)};
}

// Half vector (local frame, n = +Z) with density D(h) (h.n) for alpha = roughness^2, from u in [0, 1)^2.
inline glm::vec3 ggx_half_vector(glm::vec2 u, float alpha) {
  const float a2 = alpha * alpha;
  const float phi = 2.0f * kPi * u.x;
  const float cos_t = std::sqrt((1.0f - u.y) / (1.0f + (a2 - 1.0f) * u.y));
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

// Unit t, b with (t, b, n) right-handed and orthonormal, without branches;
// it flips where n.z changes sign (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited").
inline void orthonormal_frame(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace cr

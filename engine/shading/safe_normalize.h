#pragma once
// Normalisation that cannot produce NaN: shading runs on whatever the
// interpolation hands it (zero normals of degenerate triangles, camera on the
// surface), and one NaN pixel would poison filters and the fog downstream.
#include <cmath>

#include <glm/glm.hpp>

namespace cr {

// v / |v|, or `fallback` when v has no usable length (zero, denormal, non-finite).
inline glm::vec3 normalize_or(const glm::vec3& v, const glm::vec3& fallback) {
  const float len = glm::length(v);
  if (!(len > 1e-20f) || !std::isfinite(len)) return fallback;
  return v / len;
}

}  // namespace cr

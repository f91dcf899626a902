#pragma once
// Normalisation (and a last guard) that cannot produce NaN: shading runs on
// whatever the interpolation hands it (zero normals of degenerate triangles,
// camera on the surface), and one NaN pixel would poison filters and the fog
// downstream.
#include <cfloat>
#include <cmath>

#include <glm/glm.hpp>

namespace cr {

// x where finite, else 0: the last guard of a shaded radiance.
inline float finite_or_zero(float x) { return std::abs(x) <= FLT_MAX ? x : 0.0f; }

// Whether a length normalises: not zero, denormal, infinite or NaN. For
// vectorised loops (a select per lane); normalize_or_else's test in scalar code.
inline bool usable_length(float len) { return len > 1e-20f && len <= FLT_MAX; }

// v / |v|, or make_fallback() when v has no usable length (zero, denormal,
// non-finite): for fallbacks that cost something to compute.
template <typename MakeFallback>
glm::vec3 normalize_or_else(const glm::vec3& v, MakeFallback make_fallback) {
  const float len = glm::length(v);
  if (!(len > 1e-20f) || !std::isfinite(len)) return make_fallback();
  return v / len;
}

// v / |v|, or `fallback` when v has no usable length.
inline glm::vec3 normalize_or(const glm::vec3& v, const glm::vec3& fallback) {
  return normalize_or_else(v, [&fallback] { return fallback; });
}

}  // namespace cr

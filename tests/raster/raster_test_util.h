#pragma once
// Shared helpers of the rasterizer tests: primitives built from arrays, a
// pixel-space projection, a deterministic random source, ray casting.
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"
#include "engine/raster/tiled_rasterizer.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"

namespace cr::test {

inline Primitive make_primitive(std::vector<glm::vec3> positions, std::vector<uint32_t> indices) {
  Primitive p;
  p.positions = std::move(positions);
  p.indices = std::move(indices);
  return p;
}

// Maps pixel coordinates (x right, y down) and z = NDC depth to clip space, w = 1.
inline glm::mat4 pixel_to_clip(int width, int height) {
  glm::mat4 m(1.0f);
  m[0][0] = 2.0f / float(width);
  m[1][1] = -2.0f / float(height);
  m[3][0] = -1.0f;
  m[3][1] = 1.0f;
  return m;
}

inline RasterDraw draw_of(const Primitive& p, const glm::mat4& m, uint32_t index, bool double_sided = true) {
  RasterDraw d;
  d.primitive = &p;
  d.model_to_clip = m;
  d.double_sided = double_sided;
  d.draw_index = index;
  return d;
}

// Camera-relative model->clip for a world-space primitive (small scenes: float is enough here).
inline glm::mat4 world_to_clip(const Camera& cam) {
  glm::mat4 t(1.0f);
  t[3] = glm::vec4(-glm::vec3(cam.position), 1.0f);
  return cam.view_proj() * t;
}

// Deterministic uniform floats in [0, 1), independent of the standard library.
class Random {
 public:
  explicit Random(uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  float next() {
    s_ ^= s_ << 13;
    s_ ^= s_ >> 7;
    s_ ^= s_ << 17;
    return float(s_ >> 40) * (1.0f / 16777216.0f);
  }
  float range(float lo, float hi) { return lo + (hi - lo) * next(); }

 private:
  uint64_t s_;
};

// Ray/triangle intersection (Moller-Trumbore, double): distance t along dir
// and barycentrics (b0, b1, b2) of the hit on the triangle's plane, even when
// the hit is outside the triangle. nullopt for rays parallel to the plane.
struct RayHit {
  double t;
  glm::dvec3 b;
};
inline std::optional<RayHit> intersect_plane(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& v0,
                                             const glm::dvec3& v1, const glm::dvec3& v2) {
  const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-300) return std::nullopt;
  const glm::dvec3 s = o - v0, q = glm::cross(s, e1);
  const double u = glm::dot(s, p) / det, v = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
  return RayHit{t, glm::dvec3(1.0 - u - v, u, v)};
}

// Per-pixel fragment counts of `draws` (via the blended path over an empty
// opaque pass), to check that every sample is hit exactly once.
inline std::vector<int> count_hits(JobSystem& jobs, int width, int height, int tile_size,
                                   std::span<const RasterDraw> draws) {
  TiledRasterizer r;
  r.render_visibility(jobs, width, height, tile_size, {});
  std::vector<int> hits(size_t(width) * height, 0);
  r.render_blended(jobs, draws, [&](int x, int y, uint32_t, const Barycentrics&, float) { ++hits[size_t(y) * width + x]; });
  return hits;
}

}  // namespace cr::test

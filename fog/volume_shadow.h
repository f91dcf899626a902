#pragma once
// Sun visibility for points inside the fog, from the engine's shadow map
// (same texel layout and constant bias as ShadowMap::visibility, see
// engine/shading/shadow_map.cpp) but without a normal offset and with a 2x2
// bilinear filter instead of the wider PCF: the froxel jitter, temporal blend
// and 3x3 filter already average many positions, and the lookup runs once per
// froxel. Positions along one ray are linear in t in shadow space, so a ray
// is set up once and each lookup is a few multiply-adds.
#include <cmath>

#include <glm/glm.hpp>

#include "engine/shading/shadow_map.h"

namespace cr {

class VolumeShadow {
 public:
  VolumeShadow() = default;  // no map: every point lit
  // camera_position: the frame's camera; lookups take camera-relative points.
  VolumeShadow(const ShadowMap& map, const glm::dvec3& camera_position);

  struct Ray {
    glm::vec3 origin;  // texel x, texel y, receiver depth at t = 0
    glm::vec3 step;    // per metre along the ray
  };
  Ray ray(const glm::vec3& origin_rel, const glm::vec3& direction) const;
  // Fraction of the sun visible at origin + t * direction (1 = lit). Inline:
  // it runs once per lit froxel.
  float visibility(const Ray& r, float t) const;
  // visibility(r, t[k]) for k < n, eight points at a time where the CPU has
  // AVX2 (the same bits as the one-point lookup).
  void visibility(const Ray& r, const float* t, int n, float* out) const;
  bool empty() const { return size_ <= 0; }

 private:
  const float* depth_ = nullptr;
  int size_ = 0;
  float bias_ = 0.0f;
  glm::mat4 to_texel_{1.0f};  // camera-relative position -> (texel x, texel y, biased depth)
};

inline float VolumeShadow::visibility(const Ray& r, float t) const {
  if (size_ <= 0) return 1.0f;
  const float tx = r.origin.x + t * r.step.x;
  const float ty = r.origin.y + t * r.step.y;
  const float receiver = r.origin.z + t * r.step.z;
  const float s = float(size_);
  // Outside the map's volume nothing was recorded: lit.
  if (!(tx >= -1.0f && ty >= -1.0f && tx <= s && ty <= s && receiver >= bias_ && receiver <= 1.0f + bias_))
    return 1.0f;
  const float fx = std::floor(tx), fy = std::floor(ty);
  const float ax = tx - fx, ay = ty - fy;
  const int x0 = int(fx), y0 = int(fy);
  auto lit = [&](int x, int y) -> float {
    if (x < 0 || y < 0 || x >= size_ || y >= size_) return 1.0f;
    return depth_[size_t(y) * size_t(size_) + size_t(x)] <= receiver ? 1.0f : 0.0f;
  };
  const float top = lit(x0, y0) + (lit(x0 + 1, y0) - lit(x0, y0)) * ax;
  const float bottom = lit(x0, y0 + 1) + (lit(x0 + 1, y0 + 1) - lit(x0, y0 + 1)) * ax;
  return top + (bottom - top) * ay;
}

}  // namespace cr

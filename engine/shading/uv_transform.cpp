#include "engine/shading/uv_transform.h"

#include <cmath>

#include "engine/shading/safe_normalize.h"

namespace cr {
namespace {

// Out of line so that the restricts hold and the loop vectorises.
[[gnu::noinline]] void affine_map(int n, float a, float b, float c, float d, float t0, float t1,
                                  const float* __restrict u, const float* __restrict v, float* __restrict out_u,
                                  float* __restrict out_v) {
  for (int i = 0; i < n; ++i) {
    out_u[i] = (a * u[i] + b * v[i]) + t0;
    out_v[i] = (c * u[i] + d * v[i]) + t1;
  }
}

}  // namespace

UvAffine uv_affine(const UvTransform& t) {
  const float c = std::cos(t.rotation), s = std::sin(t.rotation);
  return {c * t.scale.x, s * t.scale.y, -s * t.scale.x, c * t.scale.y, t.offset.x, t.offset.y};
}

TexturePoints transform_uvs(const UvAffine& a, const TexturePoints& p, TransformedUvs& out) {
  affine_map(p.count, a.m00, a.m01, a.m10, a.m11, a.t0, a.t1, p.u, p.v, out.u, out.v);
  affine_map(p.count, a.m00, a.m01, a.m10, a.m11, 0.0f, 0.0f, p.du_dx, p.dv_dx, out.du_dx, out.dv_dx);
  affine_map(p.count, a.m00, a.m01, a.m10, a.m11, 0.0f, 0.0f, p.du_dy, p.dv_dy, out.du_dy, out.dv_dy);
  return {p.count, out.u, out.v, out.du_dx, out.dv_dx, out.du_dy, out.dv_dy};
}

NormalMapTurn normal_map_turn(const UvAffine& a) {
  // With w = -v (the bitangent's direction), d(u', w') = F d(u, w) for
  // F = [[m00, -m01], [-m10, m11]]; the map's frame vectors d/du' and d/dw'
  // are the columns of F^-1 = [[m11, m01], [m10, m00]] / det.
  const float det = a.m00 * a.m11 - a.m01 * a.m10;
  const float sign = det < 0.0f ? -1.0f : 1.0f;
  auto unit = [sign](float x, float y, glm::vec3 fallback) {
    return normalize_or(glm::vec3(x, y, 0.0f) * sign, fallback);
  };
  const glm::vec3 tangent = unit(a.m11, a.m10, {1.0f, 0.0f, 0.0f});
  const glm::vec3 bitangent = unit(a.m01, a.m00, {0.0f, 1.0f, 0.0f});
  return {tangent.x, bitangent.x, tangent.y, bitangent.y};
}

}  // namespace cr

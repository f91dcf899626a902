#include "engine/core/half_rounding.h"
#include "engine/shading/surface.h"

#include <cmath>
#include <vector>

#include "engine/shading/safe_normalize.h"

namespace cr {
namespace {

template <typename T>
T interpolate(const T v[3], const glm::vec3& w) {
  return w.x * v[0] + w.y * v[1] + w.z * v[2];
}

// A UV set at the barycentrics, with its screen-space derivatives.
[[gnu::always_inline]] inline void interpolate_uv(const glm::vec2 v[3], const Barycentrics& bary, glm::vec2& uv, glm::vec2& duv_dx,
                    glm::vec2& duv_dy) {
  uv = interpolate(v, bary.b);
  duv_dx = interpolate(v, bary.ddx);
  duv_dy = interpolate(v, bary.ddy);
}

// The three corners' values of a vertex stream.
template <typename T>
void corners(const std::vector<T>& stream, const uint32_t idx[3], T out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = stream[idx[k]];
}

}  // namespace

glm::vec3 orthogonal_tangent(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

TriangleSurface::TriangleSurface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                 bool front_facing, bool with_tangent, bool with_uv1, bool half_attributes)
    : has_normals_(!primitive.normals.empty()),
      has_tangents_(!primitive.tangents.empty()),
      has_uv_(!primitive.texcoords.empty()),
      has_uv1_(with_uv1 && !primitive.texcoords1.empty()),
      has_color_(!primitive.colors.empty()),
      with_tangent_(with_tangent),
      with_uv1_(with_uv1),
      front_facing_(front_facing),
      half_attributes_(half_attributes) {
  const size_t base = size_t(triangle_index) * 3;
  const uint32_t idx[3] = {primitive.indices[base], primitive.indices[base + 1], primitive.indices[base + 2]};
  const glm::mat3 world3(draw.world);
  for (int k = 0; k < 3; ++k) {
    const glm::vec3& p = primitive.positions[idx[k]];
    position_[k] = glm::vec3(draw.world * glm::vec4(p, 1.0f));
    normal_[k] = has_normals_ ? draw.normal_matrix * primitive.normals[idx[k]] : glm::vec3(0.0f);
    tangent_[k] = has_tangents_ && with_tangent ? world3 * glm::vec3(primitive.tangents[idx[k]]) : glm::vec3(0.0f);
    uv_[k] = has_uv_ ? primitive.texcoords[idx[k]] : glm::vec2(0.0f);
    color_[k] = has_color_ ? primitive.colors[idx[k]] : glm::vec4(1.0f);
  }
  if (with_uv1)
    for (int k = 0; k < 3; ++k) uv1_[k] = has_uv1_ ? primitive.texcoords1[idx[k]] : glm::vec2(0.0f);
  // A mirrored draw reverses the world-space winding, hence the sign.
  const glm::vec3 e1 = world3 * (primitive.positions[idx[1]] - primitive.positions[idx[0]]);
  const glm::vec3 e2 = world3 * (primitive.positions[idx[2]] - primitive.positions[idx[0]]);
  geometric_normal_ = normalize_or(glm::cross(e1, e2) * (draw.mirrored ? -1.0f : 1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  if (has_tangents_)
    bitangent_sign_ = (primitive.tangents[idx[0]].w < 0.0f ? -1.0f : 1.0f) * (draw.mirrored ? -1.0f : 1.0f);
}

SurfaceSample TriangleSurface::at(const Barycentrics& bary) const {
  const glm::vec3& w = bary.b;
  SurfaceSample s;
  s.front_facing = front_facing_;
  // fp16 varyings (half_attributes_): each interpolated value rounded, as add_points does.
  auto varying = [this](auto v) {
    if (half_attributes_)
      for (int c = 0; c < v.length(); ++c) v[c] = round_to_half(v[c]);
    return v;
  };
  s.position = interpolate(position_, w);
  s.normal = has_normals_ ? normalize_or(varying(interpolate(normal_, w)), geometric_normal_) : geometric_normal_;

  if (with_tangent_) {
    const glm::vec3 tangent = has_tangents_ ? varying(interpolate(tangent_, w)) : glm::vec3(0.0f);
    // Gram-Schmidt against the interpolated normal.
    s.tangent = glm::vec4(normalize_or_else(tangent - s.normal * glm::dot(s.normal, tangent),
                                            [&s] { return orthogonal_tangent(s.normal); }),
                          bitangent_sign_);
  }
  if (has_uv_) {
    interpolate_uv(uv_, bary, s.uv, s.duv_dx, s.duv_dy);
    s.uv = varying(s.uv);
  }
  if (has_uv1_) {
    interpolate_uv(uv1_, bary, s.uv1, s.duv1_dx, s.duv1_dy);
    s.uv1 = varying(s.uv1);
  }
  if (has_color_) s.color = varying(interpolate(color_, w));

  if (!front_facing_) {
    // Flip the whole frame (N, T and B = cross(N, T) * w) so a normal map
    // reads the same from the back as from the front.
    s.normal = -s.normal;
    if (with_tangent_) s.tangent = -s.tangent;
  }
  return s;
}

SurfaceSample interpolate_uv_color(const Primitive& primitive, uint32_t triangle_index, const Barycentrics& bary,
                                   bool with_uv1) {
  const size_t base = size_t(triangle_index) * 3;
  const uint32_t idx[3] = {primitive.indices[base], primitive.indices[base + 1], primitive.indices[base + 2]};
  SurfaceSample s;
  glm::vec2 uv[3];
  if (!primitive.texcoords.empty()) {
    corners(primitive.texcoords, idx, uv);
    interpolate_uv(uv, bary, s.uv, s.duv_dx, s.duv_dy);
  }
  if (with_uv1 && !primitive.texcoords1.empty()) {
    corners(primitive.texcoords1, idx, uv);
    interpolate_uv(uv, bary, s.uv1, s.duv1_dx, s.duv1_dy);
  }
  if (!primitive.colors.empty()) {
    glm::vec4 c[3];
    corners(primitive.colors, idx, c);
    s.color = interpolate(c, bary.b);
  }
  return s;
}

SurfaceSample interpolate_surface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                  const Barycentrics& bary, bool front_facing, bool with_tangent, bool with_uv1) {
  return TriangleSurface(primitive, draw, triangle_index, front_facing, with_tangent, with_uv1).at(bary);
}

}  // namespace cr

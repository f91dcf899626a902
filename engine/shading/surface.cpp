#include "engine/shading/surface.h"

#include <cmath>

#include "engine/shading/safe_normalize.h"

namespace cr {
namespace {

template <typename T>
T interpolate(const T v[3], const glm::vec3& w) {
  return w.x * v[0] + w.y * v[1] + w.z * v[2];
}

}  // namespace

glm::vec3 orthogonal_tangent(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

TriangleSurface::TriangleSurface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                 bool front_facing, bool with_tangent)
    : has_normals_(!primitive.normals.empty()),
      has_tangents_(!primitive.tangents.empty()),
      has_uv_(!primitive.texcoords.empty()),
      has_color_(!primitive.colors.empty()),
      with_tangent_(with_tangent),
      front_facing_(front_facing) {
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
  s.position = interpolate(position_, w);
  s.normal = has_normals_ ? normalize_or(interpolate(normal_, w), geometric_normal_) : geometric_normal_;

  if (with_tangent_) {
    const glm::vec3 tangent = has_tangents_ ? interpolate(tangent_, w) : glm::vec3(0.0f);
    // Gram-Schmidt against the interpolated normal.
    s.tangent = glm::vec4(normalize_or_else(tangent - s.normal * glm::dot(s.normal, tangent),
                                            [&s] { return orthogonal_tangent(s.normal); }),
                          bitangent_sign_);
  }
  if (has_uv_) {
    s.uv = interpolate(uv_, w);
    s.duv_dx = interpolate(uv_, bary.ddx);
    s.duv_dy = interpolate(uv_, bary.ddy);
  }
  if (has_color_) s.color = interpolate(color_, w);

  if (!front_facing_) {
    // Flip the whole frame (N, T and B = cross(N, T) * w) so a normal map
    // reads the same from the back as from the front.
    s.normal = -s.normal;
    if (with_tangent_) s.tangent = -s.tangent;
  }
  return s;
}

SurfaceSample interpolate_uv_color(const Primitive& primitive, uint32_t triangle_index, const Barycentrics& bary) {
  const size_t base = size_t(triangle_index) * 3;
  const uint32_t idx[3] = {primitive.indices[base], primitive.indices[base + 1], primitive.indices[base + 2]};
  SurfaceSample s;
  if (!primitive.texcoords.empty()) {
    const glm::vec2 uv[3] = {primitive.texcoords[idx[0]], primitive.texcoords[idx[1]], primitive.texcoords[idx[2]]};
    s.uv = interpolate(uv, bary.b);
    s.duv_dx = interpolate(uv, bary.ddx);
    s.duv_dy = interpolate(uv, bary.ddy);
  }
  if (!primitive.colors.empty()) {
    const glm::vec4 c[3] = {primitive.colors[idx[0]], primitive.colors[idx[1]], primitive.colors[idx[2]]};
    s.color = interpolate(c, bary.b);
  }
  return s;
}

SurfaceSample interpolate_surface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                  const Barycentrics& bary, bool front_facing, bool with_tangent) {
  return TriangleSurface(primitive, draw, triangle_index, front_facing, with_tangent).at(bary);
}

}  // namespace cr

#include "engine/shading/surface.h"

#include <cmath>

#include "engine/shading/safe_normalize.h"

namespace cr {
namespace {

template <typename T>
T interpolate(const std::vector<T>& stream, const uint32_t idx[3], const glm::vec3& w) {
  return w.x * stream[idx[0]] + w.y * stream[idx[1]] + w.z * stream[idx[2]];
}

}  // namespace

glm::vec3 orthogonal_tangent(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

SurfaceSample interpolate_surface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                  const Barycentrics& bary, bool front_facing, bool with_tangent) {
  const uint32_t idx[3] = {primitive.indices[size_t(triangle_index) * 3], primitive.indices[size_t(triangle_index) * 3 + 1],
                           primitive.indices[size_t(triangle_index) * 3 + 2]};
  const glm::vec3& w = bary.b;
  SurfaceSample s;
  s.front_facing = front_facing;
  s.position = glm::vec3(draw.world * glm::vec4(interpolate(primitive.positions, idx, w), 1.0f));

  // The geometric normal backs up missing or degenerate shading normals (so
  // it is only computed then); a mirrored draw reverses the world-space
  // winding, hence the sign.
  const glm::mat3 world3(draw.world);
  auto geometric_normal = [&] {
    const glm::vec3 e1 = world3 * (primitive.positions[idx[1]] - primitive.positions[idx[0]]);
    const glm::vec3 e2 = world3 * (primitive.positions[idx[2]] - primitive.positions[idx[0]]);
    return normalize_or(glm::cross(e1, e2) * (draw.mirrored ? -1.0f : 1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  };
  s.normal = primitive.normals.empty()
                 ? geometric_normal()
                 : normalize_or_else(draw.normal_matrix * interpolate(primitive.normals, idx, w), geometric_normal);

  if (with_tangent) {
    glm::vec3 tangent(0.0f);
    float bitangent_sign = 1.0f;
    if (!primitive.tangents.empty()) {
      const glm::vec4 t = interpolate(primitive.tangents, idx, w);
      tangent = world3 * glm::vec3(t);
      bitangent_sign = (primitive.tangents[idx[0]].w < 0.0f ? -1.0f : 1.0f) * (draw.mirrored ? -1.0f : 1.0f);
    }
    // Gram-Schmidt against the interpolated normal.
    tangent = normalize_or_else(tangent - s.normal * glm::dot(s.normal, tangent),
                                [&s] { return orthogonal_tangent(s.normal); });
    s.tangent = glm::vec4(tangent, bitangent_sign);
  }

  if (!primitive.texcoords.empty()) {
    s.uv = interpolate(primitive.texcoords, idx, w);
    s.duv_dx = interpolate(primitive.texcoords, idx, bary.ddx);
    s.duv_dy = interpolate(primitive.texcoords, idx, bary.ddy);
  }
  if (!primitive.colors.empty()) s.color = interpolate(primitive.colors, idx, w);

  if (!front_facing) {
    // Flip the whole frame (N, T and B = cross(N, T) * w) so a normal map
    // reads the same from the back as from the front.
    s.normal = -s.normal;
    if (with_tangent) s.tangent = -s.tangent;
  }
  return s;
}

}  // namespace cr

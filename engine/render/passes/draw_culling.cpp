#include "engine/render/passes/draw_culling.h"

#include <cmath>
#include <limits>

namespace cr {

glm::mat4 model_to_clip(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::mat4& world) {
  glm::dmat4 w(world);
  w[3] -= glm::dvec4(origin, 0.0);
  return glm::mat4(glm::dmat4(view_proj) * w);
}

bool aabb_in_view(const Camera& cam, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 c = 0.5f * (lo + hi) - glm::vec3(cam.position);
  const glm::vec3 e = 0.5f * (hi - lo);
  if (cam.orthographic) {
    // Inward normals and the planes' distances from the camera.
    const float hh = cam.ortho_half_height, hw = hh * cam.aspect;
    const glm::vec3 normals[6] = {cam.right, -cam.right, cam.up, -cam.up, cam.forward, -cam.forward};
    const float offsets[6] = {hw, hw, hh, hh, -cam.znear, cam.zfar};
    for (int i = 0; i < 6; ++i) {
      const glm::vec3& n = normals[i];
      const float r = e.x * std::abs(n.x) + e.y * std::abs(n.y) + e.z * std::abs(n.z);
      if (glm::dot(n, c) + r + offsets[i] < 0.0f) return false;
    }
    return true;
  }
  const float ty = std::tan(0.5f * cam.vfov_rad), tx = ty * cam.aspect;
  // Inward plane normals of the four side planes and the near plane.
  const glm::vec3 normals[5] = {
      glm::normalize(cam.forward * tx + cam.right), glm::normalize(cam.forward * tx - cam.right),
      glm::normalize(cam.forward * ty + cam.up), glm::normalize(cam.forward * ty - cam.up), cam.forward};
  for (int i = 0; i < 5; ++i) {
    const glm::vec3& n = normals[i];
    const float r = e.x * std::abs(n.x) + e.y * std::abs(n.y) + e.z * std::abs(n.z);
    const float d = glm::dot(n, c) + r - (i == 4 ? cam.znear : 0.0f);
    if (d < 0.0f) return false;
  }
  return true;
}

bool aabb_in_ortho(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::vec3& lo, const glm::vec3& hi) {
  glm::vec3 cmin(std::numeric_limits<float>::max()), cmax(-std::numeric_limits<float>::max());
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec3 c(view_proj * glm::vec4(glm::vec3(corner - origin), 1.0f));
    cmin = glm::min(cmin, c);
    cmax = glm::max(cmax, c);
  }
  return cmax.x >= -1.0f && cmin.x <= 1.0f && cmax.y >= -1.0f && cmin.y <= 1.0f && cmax.z >= 0.0f;
}

}  // namespace cr

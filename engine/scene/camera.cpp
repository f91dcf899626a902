#include "engine/scene/camera.h"

#include <cmath>

namespace cr {

Camera Camera::look_at(const glm::dvec3& position, const glm::dvec3& target, float vfov_rad,
                       float aspect, float znear) {
  Camera c;
  c.position = position;
  glm::dvec3 f = target - position;
  double len = glm::length(f);
  c.forward = len > 0.0 ? glm::vec3(f / len) : glm::vec3(0.0f, 0.0f, -1.0f);
  // Looking straight up or down: pick another reference up vector.
  glm::vec3 ref = std::abs(c.forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  c.right = glm::normalize(glm::cross(c.forward, ref));
  c.up = glm::cross(c.right, c.forward);
  c.vfov_rad = vfov_rad;
  c.aspect = aspect;
  c.znear = znear;
  return c;
}

glm::mat4 Camera::view_rotation() const {
  glm::mat4 m(1.0f);
  // Rows are right, up, -forward (view looks down -Z).
  m[0][0] = right.x;    m[1][0] = right.y;    m[2][0] = right.z;
  m[0][1] = up.x;       m[1][1] = up.y;       m[2][1] = up.z;
  m[0][2] = -forward.x; m[1][2] = -forward.y; m[2][2] = -forward.z;
  return m;
}

glm::mat4 Camera::projection() const {
  glm::mat4 p(0.0f);
  if (orthographic) {
    // z_clip = (zfar - depth) / (zfar - znear), w = 1.
    p[0][0] = 1.0f / (ortho_half_height * aspect);
    p[1][1] = 1.0f / ortho_half_height;
    p[2][2] = 1.0f / (zfar - znear);
    p[3][2] = zfar / (zfar - znear);
    p[3][3] = 1.0f;
    return p;
  }
  const float f = 1.0f / std::tan(0.5f * vfov_rad);
  p[0][0] = f / aspect;
  p[1][1] = f;
  p[2][3] = -1.0f;   // w = -z_view (distance in front of the camera)
  p[3][2] = znear;   // z = znear, so z/w = znear / depth
  return p;
}

glm::vec3 Camera::ray_direction(float px, float py, int width, int height) const {
  return PixelRays(*this, width, height).direction(px, py);
}

PixelRays::PixelRays(const Camera& camera, int width, int height)
    : forward_(camera.forward),
      right_(camera.right),
      up_(camera.up),
      // Parallel rays: a zero field of view makes every direction forward.
      tan_half_y_(camera.orthographic ? 0.0f : std::tan(0.5f * camera.vfov_rad)),
      aspect_(camera.aspect),
      width_(float(width)),
      height_(float(height)) {}

}  // namespace cr

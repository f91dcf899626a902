#pragma once
// The view camera of one frame. Position is double (planet-scale scenes);
// rendering is camera-relative: clip = view_proj * vec4(world - position, 1).
// Projection is reversed-Z with an infinite far plane: NDC depth = znear / view
// depth, so 1 at the near plane and 0 at infinity; float32 keeps ~7 significant
// digits of relative depth precision over the whole range (no far clip needed).
#include <glm/glm.hpp>

namespace cr {

struct Camera {
  glm::dvec3 position{0.0};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  glm::vec3 right{1.0f, 0.0f, 0.0f};     // unit, forward x up
  float vfov_rad = 1.0471976f;
  float aspect = 16.0f / 9.0f;
  float znear = 0.1f;

  static Camera look_at(const glm::dvec3& position, const glm::dvec3& target, float vfov_rad,
                        float aspect, float znear);
  glm::mat4 view_rotation() const;  // world (camera-relative) -> view, no translation
  glm::mat4 projection() const;     // reversed-Z infinite perspective (OpenGL-style clip, z in [0,w])
  glm::mat4 view_proj() const { return projection() * view_rotation(); }
  // Unit world-space direction through pixel (px, py) of a width x height image;
  // pixel centres are at integer + 0.5, y grows downwards.
  glm::vec3 ray_direction(float px, float py, int width, int height) const;
};

// Camera::ray_direction for many pixels of one image: the projection's
// tangent is computed once instead of per ray (same operations, same bits).
class PixelRays {
 public:
  PixelRays(const Camera& camera, int width, int height);
  glm::vec3 direction(float px, float py) const {
    const float sx = (2.0f * px / width_ - 1.0f) * tan_half_y_ * aspect_;
    const float sy = (1.0f - 2.0f * py / height_) * tan_half_y_;
    return glm::normalize(forward_ + sx * right_ + sy * up_);
  }

 private:
  glm::vec3 forward_, right_, up_;
  float tan_half_y_, aspect_, width_, height_;
};

}  // namespace cr

#pragma once
// The view camera of one frame. Position is double (planet-scale scenes);
// rendering is camera-relative: clip = view_proj * vec4(world - position, 1).
// Projection is reversed-Z with an infinite far plane: NDC depth = znear / view
// depth, so 1 at the near plane and 0 at infinity; float32 keeps ~7 significant
// digits of relative depth precision over the whole range (no far clip needed).
#include <cmath>

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
  // Orthographic views (glTF orthographic cameras): parallel rays along
  // forward through a view 2 * ortho_half_height metres high, depths in
  // [znear, zfar] mapped to NDC depth 1..0 (reversed-Z, with a far plane).
  // vfov_rad is unused for them.
  bool orthographic = false;
  float ortho_half_height = 1.0f;
  float zfar = 1.0f;

  static Camera look_at(const glm::dvec3& position, const glm::dvec3& target, float vfov_rad,
                        float aspect, float znear);
  glm::mat4 view_rotation() const;  // world (camera-relative) -> view, no translation
  // Reversed-Z infinite perspective, or reversed-Z orthographic (OpenGL-style clip, z in [0,w]).
  glm::mat4 projection() const;
  // View depth (metres along forward) of a reversed-Z NDC depth d > 0.
  float view_depth(float d) const {
    return orthographic ? zfar - d * (zfar - znear) : znear / d;
  }
  glm::mat4 view_proj() const { return projection() * view_rotation(); }
  // Unit world-space direction through pixel (px, py) of a width x height image;
  // pixel centres are at integer + 0.5, y grows downwards. (Orthographic:
  // forward for every pixel; the rays start on the view plane instead.)
  glm::vec3 ray_direction(float px, float py, int width, int height) const;
};

// Camera::ray_direction for many pixels of one image: the projection's
// tangent is computed once instead of per ray (same operations, same bits).
class PixelRays {
 public:
  PixelRays(const Camera& camera, int width, int height);
  glm::vec3 direction(float px, float py) const { return through(screen_x(px), screen_y(py)); }
  // The steps of direction(), for loops that reuse a row's or column's term:
  // the image-plane coordinates of a pixel (at unit distance) and the unit
  // ray through them (glm::normalize's operations, spelled out so loops over
  // a row vectorise).
  float screen_x(float px) const { return (2.0f * px / width_ - 1.0f) * tan_half_y_ * aspect_; }
  float screen_y(float py) const { return (1.0f - 2.0f * py / height_) * tan_half_y_; }
  glm::vec3 through(float sx, float sy) const {
    const float x = forward_.x + sx * right_.x + sy * up_.x;
    const float y = forward_.y + sx * right_.y + sy * up_.y;
    const float z = forward_.z + sx * right_.z + sy * up_.z;
    const float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
    return glm::vec3(x * inv, y * inv, z * inv);
  }

 private:
  glm::vec3 forward_, right_, up_;
  float tan_half_y_, aspect_, width_, height_;
};

}  // namespace cr

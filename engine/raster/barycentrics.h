#pragma once
// Perspective-correct barycentric weights of a pixel with respect to the
// ORIGINAL (unclipped) triangle's three vertices, and their screen-space
// derivatives (per pixel step in x and in y). Attributes are interpolated as
// a = b.x*a0 + b.y*a1 + b.z*a2; derivatives give texture LOD analytically.
#include <glm/glm.hpp>

namespace cr {

struct Barycentrics {
  glm::vec3 b{1.0f, 0.0f, 0.0f};
  glm::vec3 ddx{0.0f};
  glm::vec3 ddy{0.0f};
};

}  // namespace cr

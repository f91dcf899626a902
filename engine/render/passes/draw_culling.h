#pragma once
// Which draws a view or a shadow projection can see, and their
// camera-relative model-to-clip matrices.
#include <glm/glm.hpp>

#include "engine/scene/camera.h"

namespace cr {

// Camera-relative model -> clip, composed in double so a large camera offset
// does not cost float precision (the float matrix only holds small numbers).
glm::mat4 model_to_clip(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::mat4& world);
// Conservative test of a world AABB against the camera frustum (infinite far),
// or an orthographic camera's box.
bool aabb_in_view(const Camera& cam, const glm::vec3& lo, const glm::vec3& hi);
// Whether a world AABB overlaps the clip volume of an orthographic projection
// (x, y in [-1, 1]; z below 0 is beyond the map's depth range).
bool aabb_in_ortho(const glm::mat4& view_proj, const glm::dvec3& origin, const glm::vec3& lo, const glm::vec3& hi);

}  // namespace cr

#pragma once
// Back-to-front order of blended draws: by the view depth of each draw's
// world-AABB centre, farthest first. A stable sort on double depths, so equal
// depths keep submission order and the order is the same on every run.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

// Indices into `world_centres`, farthest from the camera (along `forward`) first.
std::vector<uint32_t> back_to_front_order(std::span<const glm::dvec3> world_centres,
                                          const glm::dvec3& camera_position, const glm::vec3& forward);

}  // namespace cr

#include "engine/raster/blend_order.h"

#include <algorithm>
#include <numeric>

namespace cr {

std::vector<uint32_t> back_to_front_order(std::span<const glm::dvec3> world_centres,
                                          const glm::dvec3& camera_position, const glm::vec3& forward) {
  std::vector<double> depth(world_centres.size());
  for (size_t i = 0; i < world_centres.size(); ++i)
    depth[i] = glm::dot(world_centres[i] - camera_position, glm::dvec3(forward));
  std::vector<uint32_t> order(world_centres.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return depth[a] > depth[b]; });
  return order;
}

}  // namespace cr

#include "engine/render/frame_memory.h"

#include <string>

#include "engine/render/frame_buffers.h"

namespace cr {

void estimate_frame_memory(const Profile& p, MemoryBudget& memory) {
  const size_t pixels = saturating_product({size_t(p.width), size_t(p.height)});
  const std::string size = std::to_string(p.width) + "x" + std::to_string(p.height);
  // FrameBuffers' colour, depth, distance and display, and the visibility
  // buffer's triangle id and depth per pixel.
  const size_t per_pixel = sizeof(glm::vec3) + 2 * sizeof(float) + 3 + 2 * sizeof(uint32_t);
  memory.charge("frame buffers of " + size, p.path, "resolution", saturating_product({pixels, per_pixel}));
  if (p.msaa_samples > 1) {
    // Worst case: every pixel mixed (its id, each sample's id and depth) and
    // one fragment per sample, held in the tile rows and in the frame's list.
    const size_t samples = size_t(p.msaa_samples);
    const size_t per_edge_pixel = sizeof(uint32_t) * 2 + samples * (2 * sizeof(uint32_t) + 2 * sizeof(EdgeFragment));
    memory.charge(std::to_string(samples) + " samples per pixel at " + size, p.path, "antialiasing",
                  saturating_product({pixels, per_edge_pixel}));
  }
  if (p.shadow_map_size > 0) {
    const size_t texels = saturating_product({size_t(p.shadow_map_size), size_t(p.shadow_map_size)});
    // This frame's map and the last one's (kept where the projection moved).
    memory.charge("two shadow maps of " + std::to_string(p.shadow_map_size) + "^2", p.path, "shadow_map_size",
                  saturating_product({texels, 2 * sizeof(float)}));
  }
}

}  // namespace cr

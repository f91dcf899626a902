#include "engine/render/frame_memory.h"

#include <string>

#include "engine/render/frame_buffers.h"

namespace cr {

void estimate_frame_memory(const Profile& p, MemoryBudget& memory) {
  const auto dims = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  const size_t output_pixels = saturating_product({size_t(p.width), size_t(p.height)});
  const size_t pixels = saturating_product({size_t(p.render_width()), size_t(p.render_height())});
  const std::string size = dims(p.render_width(), p.render_height());
  // FrameBuffers' colour, depth and distance, and the display image at the output size.
  const size_t buffer_per_pixel = sizeof(glm::vec3) + 2 * sizeof(float);
  const size_t display_per_pixel = 3;
  // The visibility buffer's triangle id and depth per pixel.
  const size_t visibility_per_pixel = 2 * sizeof(uint32_t);
  if (p.scaled()) {
    // The scene renders into buffers of the internal size, upscaled into the output's.
    memory.charge("internal frame buffers of " + size, p.path, "render_scale",
                  saturating_product({pixels, buffer_per_pixel + visibility_per_pixel}));
    memory.charge("output frame buffers of " + dims(p.width, p.height), p.path, "resolution",
                  saturating_product({output_pixels, buffer_per_pixel + display_per_pixel}));
  } else {
    memory.charge("frame buffers of " + size, p.path, "resolution",
                  saturating_product({pixels, buffer_per_pixel + display_per_pixel + visibility_per_pixel}));
  }
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

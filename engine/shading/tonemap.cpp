#include "engine/shading/tonemap.h"

namespace cr {

void resolve_to_srgb8(const glm::vec3* hdr, size_t count, float ev100, uint8_t* rgb_out) {
  const float exposure = exposure_scale(ev100);
  for (size_t i = 0; i < count; ++i) resolve_pixel(hdr[i], exposure, rgb_out + 3 * i);
}

}  // namespace cr

#include "engine/scene/image_texels.h"

#include "engine/core/srgb.h"

namespace cr {

void decode_texels(Image& image) {
  const std::array<float, 256>& srgb = srgb_decode_table();
  auto unorm = [](uint8_t code) { return float(code) / 255.0f; };
  auto color = [&](uint8_t code) { return image.srgb ? srgb[code] : unorm(code); };
  for (MipLevel& m : image.mips) {
    m.texels.resize(size_t(m.width) * size_t(m.height));
    for (size_t i = 0; i < m.texels.size(); ++i) {
      const uint8_t* p = &m.rgba[i * 4];
      m.texels[i] = glm::vec4(color(p[0]), color(p[1]), color(p[2]), unorm(p[3]));
    }
  }
}

}  // namespace cr

#include "engine/scene/image_texels.h"

#include <array>

#include "engine/core/srgb.h"

namespace cr {
namespace {

// Value of each 8-bit code of a linear (UNORM) channel, code / 255, so that
// every channel decodes by one lookup like the sRGB ones.
const std::array<float, 256>& unorm_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i) / 255.0f;
    return t;
  }();
  return table;
}

}  // namespace

TexelDecoder::TexelDecoder(const Image& image)
    : rgb(image.srgb ? srgb_decode_table().data() : unorm_decode_table().data()),
      alpha(unorm_decode_table().data()) {}

size_t decoded_texel_bytes(const Image& image) {
  size_t texels = 0;
  for (const MipLevel& m : image.mips) texels += size_t(m.width) * size_t(m.height);
  return texels * sizeof(glm::vec4);
}

void decode_texels(Image& image) {
  const TexelDecoder decode(image);
  for (MipLevel& m : image.mips) {
    m.texels.resize(size_t(m.width) * size_t(m.height));
    for (size_t i = 0; i < m.texels.size(); ++i) m.texels[i] = decode(m, i);
  }
}

}  // namespace cr

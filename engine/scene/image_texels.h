#pragma once
// Decoding of an image's RGBA8 texels into linear floats: per texel through
// the image's tables (sRGB or UNORM colour, UNORM alpha), or a whole chain at
// once into MipLevel::texels, the copy texture sampling reads when present.
// A decoded chain costs 16 bytes a texel besides RGBA8's 4 and saves the
// table lookups of every filtered read; the loader decodes images while they
// fit the profile's budget (texture_decode_budget_mb). Both ways give the
// same floats, so sampling results do not depend on the budget.
#include <cstddef>

#include "engine/scene/scene.h"

namespace cr {

// The decode tables of one image, chosen once per lookup rather than per texel.
struct TexelDecoder {
  const float* rgb;
  const float* alpha;
  explicit TexelDecoder(const Image& image);
  glm::vec4 operator()(const MipLevel& m, size_t texel) const {
    const uint8_t* p = &m.rgba[texel * 4];
    return {rgb[p[0]], rgb[p[1]], rgb[p[2]], alpha[p[3]]};
  }
};

// Bytes that decode_texels adds for the image's whole chain.
size_t decoded_texel_bytes(const Image& image);

// Fills MipLevel::texels of every level from its rgba. Run it after the chain
// is complete (generate_mips) and again whenever rgba changes.
void decode_texels(Image& image);

}  // namespace cr

#pragma once
// Decoding of an image's RGBA8 levels into the linear floats texture
// sampling reads (MipLevel::texels), once at load instead of per lookup.
#include "engine/scene/scene.h"

namespace cr {

// Fills MipLevel::texels of every level from its rgba: the colour channels
// of an sRGB image through srgb_decode_table() (core/srgb.h), every other
// channel as code / 255. Run it after the chain is complete (generate_mips)
// and again whenever rgba changes.
void decode_texels(Image& image);

}  // namespace cr

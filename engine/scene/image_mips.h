#pragma once
// Mip chain generation for RGBA8 images.
#include "engine/scene/scene.h"

namespace cr {

// Replaces image.mips[1..] by a full chain down to 1x1 built from mips[0].
// Level sizes are max(1, floor(previous / 2)), so non-power-of-two images work;
// each texel is the box average of the 2x2 (or, next to an odd edge, up to 3x3)
// texels of the level above it covers. sRGB images are averaged in linear light
// and re-encoded (averaging encoded values darkens: black/white gives 128, not
// the correct 188); alpha is always linear.
// With drop > 0 the chain keeps only its levels from `drop` on (mips[0]
// becomes the chain's level `drop`, at most its 1x1 level): each level above
// is freed as soon as the next is made, so at most two of them are held.
void generate_mips(Image& image, int drop = 0);

}  // namespace cr

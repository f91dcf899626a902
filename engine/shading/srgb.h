#pragma once
// The sRGB transfer function (IEC 61966-2-1): decoding of 8-bit texels to
// linear and encoding of linear values for display.
#include <array>
#include <cstdint>

namespace cr {

// Decodes one sRGB-encoded value in [0, 1] to linear.
float srgb_to_linear(float encoded);
// The sRGB OETF: encodes a linear value in [0, 1] (clamped) for display.
float linear_to_srgb(float linear);
// Linear value of each 8-bit sRGB code, built once: texture fetches decode by
// lookup instead of a pow() per texel.
const std::array<float, 256>& srgb_decode_table();

}  // namespace cr

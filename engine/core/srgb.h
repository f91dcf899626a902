#pragma once
// The sRGB transfer function (IEC 61966-2-1) and 8-bit quantisation, shared by
// texture decoding, the display transform and image files.
#include <array>
#include <cstdint>

namespace cr {

float srgb_to_linear(float encoded);
// Linear [0, 1] to sRGB-encoded [0, 1]; NaN and negatives give 0, above 1 gives 1.
float linear_to_srgb(float linear);
// Decoded value of each 8-bit sRGB code.
const std::array<float, 256>& srgb_decode_table();

// Display value in [0, 1] to the nearest 8-bit code (round half up); NaN maps
// to 0 so a broken pixel shows up black instead of as undefined behaviour.
inline uint8_t quantize_unorm8(float display) {
  if (!(display > 0.0f)) return 0;
  if (display >= 1.0f) return 255;
  return uint8_t(display * 255.0f + 0.5f);
}

}  // namespace cr

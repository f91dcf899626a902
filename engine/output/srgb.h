#pragma once
// The sRGB transfer function (IEC 61966-2-1) and 8-bit quantisation.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cr {

inline float srgb_to_linear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f
                             : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

inline float linear_to_srgb(float linear) {
  return linear <= 0.0031308f ? 12.92f * linear
                              : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

// Display value in [0,1] to the nearest 8-bit code; NaN maps to 0 so a broken
// pixel shows up black instead of as undefined behaviour in the cast.
inline uint8_t quantize_unorm8(float display) {
  if (!(display > 0.0f)) return 0;
  if (display >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(display * 255.0f));
}

}  // namespace cr

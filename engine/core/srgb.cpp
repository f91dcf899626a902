#include "engine/core/srgb.h"

#include <algorithm>
#include <cmath>

namespace cr {

float srgb_to_linear(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  // NaN fails every comparison; std::clamp would pass it through.
  if (!(linear > 0.0f)) return 0.0f;
  linear = std::min(linear, 1.0f);
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

const std::array<float, 256>& srgb_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.0f);
    return t;
  }();
  return table;
}

}  // namespace cr

#include "engine/scene/image_mips.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace cr {

namespace {

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

const std::array<float, 256>& srgb_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = static_cast<float>(srgb_to_linear(i / 255.0));
    return t;
  }();
  return table;
}

// Nearest 8-bit sRGB code of a linear value: binary search over the midpoints
// between the decoded codes, so encode(decode(c)) == c exactly.
uint8_t linear_to_srgb8(float linear) {
  static const std::array<float, 255> midpoints = [] {
    std::array<float, 255> m{};
    for (int i = 0; i < 255; ++i) m[i] = static_cast<float>(srgb_to_linear((i + 0.5) / 255.0));
    return m;
  }();
  return static_cast<uint8_t>(std::upper_bound(midpoints.begin(), midpoints.end(), linear) - midpoints.begin());
}

MipLevel downsample(const MipLevel& src, bool srgb) {
  MipLevel dst;
  dst.width = std::max(1, src.width / 2);
  dst.height = std::max(1, src.height / 2);
  dst.rgba.resize(static_cast<size_t>(dst.width) * dst.height * 4);
  const std::array<float, 256>& decode = srgb_decode_table();
  for (int y = 0; y < dst.height; ++y) {
    // Source rows [y0, y1) covered by this texel: 2 rows, 3 at an odd edge.
    int y0 = static_cast<int>(static_cast<long long>(y) * src.height / dst.height);
    int y1 = static_cast<int>(static_cast<long long>(y + 1) * src.height / dst.height);
    for (int x = 0; x < dst.width; ++x) {
      int x0 = static_cast<int>(static_cast<long long>(x) * src.width / dst.width);
      int x1 = static_cast<int>(static_cast<long long>(x + 1) * src.width / dst.width);
      float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      for (int sy = y0; sy < y1; ++sy) {
        const uint8_t* row = src.rgba.data() + (static_cast<size_t>(sy) * src.width) * 4;
        for (int sx = x0; sx < x1; ++sx) {
          const uint8_t* p = row + static_cast<size_t>(sx) * 4;
          for (int c = 0; c < 3; ++c) sum[c] += srgb ? decode[p[c]] : static_cast<float>(p[c]);
          sum[3] += static_cast<float>(p[3]);
        }
      }
      float inv = 1.0f / static_cast<float>((y1 - y0) * (x1 - x0));
      uint8_t* out = dst.rgba.data() + (static_cast<size_t>(y) * dst.width + x) * 4;
      for (int c = 0; c < 4; ++c) {
        float avg = sum[c] * inv;
        out[c] = srgb && c < 3 ? linear_to_srgb8(avg)
                               : static_cast<uint8_t>(std::clamp(std::lround(avg), 0l, 255l));
      }
    }
  }
  return dst;
}

}  // namespace

void generate_mips(Image& image, int drop) {
  if (image.mips.empty()) throw std::invalid_argument("generate_mips: image '" + image.name + "' has no base level");
  image.mips.resize(1);
  while (image.mips.back().width > 1 || image.mips.back().height > 1) {
    image.mips.push_back(downsample(image.mips.back(), image.srgb));
    if (drop > 0) {
      image.mips.erase(image.mips.begin());
      --drop;
    }
  }
}

}  // namespace cr

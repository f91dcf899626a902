#include "engine/output/color_map.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/srgb.h"

namespace cr {
namespace {

// magma at indices 0, 16, ..., 240, 255 of its 256-entry table.
constexpr float kMagmaIndex[17] = {0, 16, 32, 48, 64, 80, 96, 112, 128,
                                   144, 160, 176, 192, 208, 224, 240, 255};
constexpr float kMagma[17][3] = {
    {0.001462f, 0.000466f, 0.013866f}, {0.039608f, 0.031090f, 0.133515f},
    {0.113094f, 0.065492f, 0.276784f}, {0.211718f, 0.061992f, 0.418647f},
    {0.316654f, 0.071690f, 0.485380f}, {0.414709f, 0.110431f, 0.504662f},
    {0.512831f, 0.148179f, 0.507648f}, {0.613617f, 0.181811f, 0.498536f},
    {0.716387f, 0.214982f, 0.475290f}, {0.816914f, 0.255895f, 0.436461f},
    {0.904281f, 0.319610f, 0.388137f}, {0.960949f, 0.418323f, 0.359630f},
    {0.986700f, 0.535582f, 0.382210f}, {0.996096f, 0.653659f, 0.446213f},
    {0.996898f, 0.769591f, 0.534892f}, {0.992440f, 0.884330f, 0.640099f},
    {0.987053f, 0.991438f, 0.749504f}};

}  // namespace

std::array<uint8_t, 3> magma(float t) {
  const float index = (t > 0.0f ? std::min(t, 1.0f) : 0.0f) * 255.0f;  // NaN -> 0
  size_t segment = 0;
  while (segment + 2 < std::size(kMagmaIndex) && index > kMagmaIndex[segment + 1]) ++segment;
  const float f = (index - kMagmaIndex[segment]) / (kMagmaIndex[segment + 1] - kMagmaIndex[segment]);
  std::array<uint8_t, 3> rgb{};
  for (int c = 0; c < 3; ++c)
    rgb[c] = quantize_unorm8(kMagma[segment][c] + f * (kMagma[segment + 1][c] - kMagma[segment][c]));
  return rgb;
}

Image8 heatmap_rgb8(const std::vector<float>& values, int width, int height, float scale) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (width <= 0 || height <= 0 || values.size() != pixels)
    throw Error("heat map: " + std::to_string(values.size()) + " values for " +
                std::to_string(width) + "x" + std::to_string(height) + " pixels");
  Image8 image{width, height, 3, std::vector<uint8_t>(pixels * 3)};
  const float inverse = scale > 0.0f ? 1.0f / scale : 0.0f;
  for (size_t i = 0; i < pixels; ++i) {
    const auto rgb = magma(values[i] * inverse);
    std::copy(rgb.begin(), rgb.end(), image.data.begin() + static_cast<std::ptrdiff_t>(i * 3));
  }
  return image;
}

}  // namespace cr

#pragma once
// Perceptually ordered colour map for error heat maps.
#include <array>
#include <cstdint>
#include <vector>

#include "engine/output/image.h"

namespace cr {

// Matplotlib's "magma" (van der Walt & Smith, as used by FLIP's error maps),
// linearly interpolated between 17 samples; t is clamped to [0,1]
// (0 = black, 1 = pale yellow). Returns 8-bit display (sRGB) values.
std::array<uint8_t, 3> magma(float t);

// Colours `values` (width * height, row-major) by magma(value / scale).
Image8 heatmap_rgb8(const std::vector<float>& values, int width, int height, float scale = 1.0f);

}  // namespace cr

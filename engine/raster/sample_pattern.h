#pragma once
// Sample positions of multisampled rasterisation: the standard Direct3D
// patterns for 2, 4 and 8 samples (rotated grids, 1/16-pixel lattice), as
// offsets from the pixel centre with y down. Each pattern's offsets sum to
// zero, so the mean of a plane over the samples is its value at the centre.
#include <array>
#include <cstdint>

#include "engine/core/error.h"
#include "engine/raster/raster_types.h"

namespace cr {

inline constexpr int kMaxSamples = 8;

struct SamplePattern {
  int count = 1;
  std::array<int8_t, kMaxSamples> x{}, y{};  // sixteenths of a pixel from the centre

  // Offset in subpixels (kSubpixelScale per pixel), exact.
  int32_t dx_subpixels(int s) const { return int32_t(x[size_t(s)]) * (kSubpixelScale / 16); }
  int32_t dy_subpixels(int s) const { return int32_t(y[size_t(s)]) * (kSubpixelScale / 16); }
  // Offset in pixels.
  float dx(int s) const { return float(x[size_t(s)]) / 16.0f; }
  float dy(int s) const { return float(y[size_t(s)]) / 16.0f; }
  // Largest |offset| of any sample along either axis, in subpixels.
  int32_t margin_subpixels() const {
    int32_t m = 0;
    for (int s = 0; s < count; ++s) {
      const int32_t ax = dx_subpixels(s) < 0 ? -dx_subpixels(s) : dx_subpixels(s);
      const int32_t ay = dy_subpixels(s) < 0 ? -dy_subpixels(s) : dy_subpixels(s);
      m = ax > m ? ax : m;
      m = ay > m ? ay : m;
    }
    return m;
  }
};

// The pattern of 1 (the centre), 2, 4 or 8 samples.
inline SamplePattern sample_pattern(int count) {
  switch (count) {
    case 1: return {1, {0}, {0}};
    case 2: return {2, {4, -4}, {4, -4}};
    case 4: return {4, {-2, 6, -6, 2}, {-6, -2, 2, 6}};
    case 8: return {8, {1, -1, 5, -3, -5, -7, 3, 7}, {-3, 3, 1, -5, 5, -1, 7, -7}};
    default: throw Error("rasterizer: " + std::to_string(count) + " samples per pixel (1, 2, 4 or 8)");
  }
}

}  // namespace cr

#pragma once
// Plain image containers passed between the renderer, file I/O and the
// image comparison. Rows top to bottom, pixels left to right, interleaved.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cr {

// Three floats per pixel: scene-linear radiance or display-encoded values;
// which one is up to the producer (file readers say it in their names).
struct ImageRGBf {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // width * height * 3

  ImageRGBf() = default;
  ImageRGBf(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  float* pixel(int x, int y) { return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  const float* pixel(int x, int y) const {
    return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
  }
};

// 8-bit image with 1..4 interleaved channels (PNG data).
struct Image8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<uint8_t> data;  // width * height * channels
};

}  // namespace cr

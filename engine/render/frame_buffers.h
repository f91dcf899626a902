#pragma once
// Per-frame full-resolution buffers. Colour is linear HDR radiance (cd/m^2)
// before exposure. Row-major, y down, index = y * width + x.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

struct FrameBuffers {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> color;
  std::vector<float> depth;     // reversed-Z NDC depth; 0 = nothing drawn (sky)
  std::vector<float> distance;  // metres from the camera along the view ray; +inf for sky
  std::vector<uint8_t> display; // resolved sRGB 8-bit RGB (exposure + tonemap), 3 bytes per pixel

  void resize(int w, int h) {
    width = w;
    height = h;
    color.assign(size_t(w) * h, glm::vec3(0.0f));
    depth.assign(size_t(w) * h, 0.0f);
    distance.assign(size_t(w) * h, std::numeric_limits<float>::infinity());
    display.assign(size_t(w) * h * 3, 0);
  }
  size_t index(int x, int y) const { return size_t(y) * width + x; }
};

}  // namespace cr

#pragma once
// Per-frame buffers of one size: the output's or, with a render scale below
// 1, the internal one the scene renders at. Colour is linear HDR radiance (cd/m^2)
// before exposure. Row-major, y down, index = y * width + x.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

// With multisampling, a pixel whose samples do not all see one surface (an
// edge pixel) is shaded and composited as fragments: one per distinct surface
// (or the sky) among its samples, each at its samples' centroid with its own
// depth and distance, then resolved to the pixel as the weighted sum.
struct EdgeFragment {
  uint32_t pixel = 0;        // y * width + x
  uint32_t triangle = 0;     // visibility-buffer id; kNoTriangle (raster_types.h): the sky
  float x = 0.0f, y = 0.0f;  // screen position in pixels (the centre of pixel (i, j) is i + 0.5, j + 0.5)
  float weight = 0.0f;       // share of the pixel's samples
  float depth = 0.0f;        // reversed-Z depth at (x, y); 0 for the sky
  float distance = 0.0f;     // metres along the ray through (x, y); +inf for the sky
  glm::vec3 color{0.0f};     // linear radiance, as `color` is for a pixel
};

struct FrameBuffers {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> color;
  std::vector<float> depth;     // reversed-Z NDC depth; 0 = nothing drawn (sky)
  std::vector<float> distance;  // metres from the camera along the view ray; +inf for sky
  std::vector<uint8_t> display; // resolved sRGB 8-bit RGB (exposure + tonemap), 3 bytes per pixel
  // Edge pixels' fragments, each pixel's together (empty without multisampling). At an edge pixel, depth and distance hold the
  // farthest fragment's (so depth-aware culling keeps what any fragment
  // needs) and color is replaced by the fragments' resolve.
  std::vector<EdgeFragment> fragments;

  // `with_display` false: no display image (internal buffers that are
  // upscaled before the display transform).
  void resize(int w, int h, bool with_display = true) {
    width = w;
    height = h;
    color.assign(size_t(w) * h, glm::vec3(0.0f));
    depth.assign(size_t(w) * h, 0.0f);
    distance.assign(size_t(w) * h, std::numeric_limits<float>::infinity());
    display.assign(with_display ? size_t(w) * h * 3 : 0, 0);
    fragments.clear();
  }
  size_t index(int x, int y) const { return size_t(y) * width + x; }
};

}  // namespace cr

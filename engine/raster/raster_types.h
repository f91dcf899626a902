#pragma once
// Inputs, outputs and limits of the tiled rasterizer shared by its stages.
//
// Coordinates: pixel (x, y) covers [x, x+1) x [y, y+1) with y growing down;
// its sample is the centre (x + 0.5, y + 0.5). Clip space is OpenGL-style
// with reversed Z: NDC z = 1 at the near plane, 0 at infinity (or the far end
// of an orthographic range). Depth test is GREATER (larger = nearer).
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "engine/raster/barycentrics.h"
#include "engine/scene/scene.h"

namespace cr {

// Screen positions are snapped to 1/256 pixel.
inline constexpr int kSubpixelBits = 8;
inline constexpr int kSubpixelScale = 1 << kSubpixelBits;
// Largest image edge. With the guard band below, snapped coordinates stay
// within +-2^15 pixels = +-2^23 subpixels, which bounds every integer in the
// edge functions (see triangle_setup.h).
inline constexpr int kMaxImageSize = 16384;
// Pixels of guard band beyond each image edge; geometry further out is clipped.
inline constexpr int kGuardBandPixels = 8192;

inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;

// One primitive to rasterise. model_to_clip already holds the camera-relative
// translation (computed in double by the caller), so this stage only needs
// float mat4 * vec4.
struct RasterDraw {
  const Primitive* primitive = nullptr;
  glm::mat4 model_to_clip{1.0f};
  bool double_sided = false;
  bool mirrored = false;    // det(world) < 0: the winding that means "front" is flipped
  bool alpha_mask = false;  // coverage decided per pixel by the CoverageFn
  uint32_t draw_index = 0;  // reported back by TiledRasterizer::ref()
};

// The original triangle behind a triangle id.
struct TriangleRef {
  uint32_t draw_index = 0;
  uint32_t triangle_index = 0;  // index into the primitive's triangle list
  bool front_facing = true;     // the side the viewer sees (for double-sided normal flips)
};

// Alpha-mask coverage: called only where the depth test passes; true keeps the pixel.
using CoverageFn = std::function<bool(uint32_t triangle_id, const Barycentrics&)>;
// Blended fragment that passed the opaque depth test, delivered per pixel in
// primitive order; coverage: the share of the pixel's samples it covers (1
// with one sample per pixel).
using FragmentFn =
    std::function<void(int x, int y, uint32_t triangle_id, const Barycentrics&, float coverage)>;

// Multisampling: the pixels of one tile whose samples do not all see the
// same triangle, in row-major order, with every sample's id and depth
// (pattern.count per pixel, in the pattern's order).
struct MixedSamples {
  std::vector<uint32_t> pixels;    // y * width + x
  std::vector<uint32_t> triangle;  // kNoTriangle: that sample sees nothing
  std::vector<float> depth;
  void clear() {
    pixels.clear();
    triangle.clear();
    depth.clear();
  }
};

struct TileStats {
  uint64_t triangles = 0;       // screen triangles binned to the tile
  uint64_t pixels_covered = 0;  // samples inside a triangle (before depth and alpha tests)
  uint64_t pixels_passed = 0;   // samples that passed depth (and alpha-mask) tests
};

// Counts of one render call, for throughput reports (Mtris/s, Mpixels/s).
struct RasterStats {
  uint64_t triangles_in = 0;        // triangles of all draws
  uint64_t triangles_culled = 0;    // back faces, degenerate (zero area, NaN), outside the view
  uint64_t triangles_clipped = 0;   // needed near/guard-band clipping
  uint64_t triangles_visible = 0;   // original triangles surviving culling (= triangle ids issued)
  uint64_t screen_triangles = 0;    // after clipping and fanning, with non-empty pixel bounds
  uint64_t tile_triangle_pairs = 0; // binned (tile, screen triangle) pairs
  uint64_t pixels_covered = 0;
  uint64_t pixels_passed = 0;
  int tiles_x = 0;
  int tiles_y = 0;
  std::vector<TileStats> tiles;     // row-major, tiles_x * tiles_y
};

}  // namespace cr

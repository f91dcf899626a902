#pragma once
// Triangle setup: cull, clip, snap to fixed point and build the integer edge
// functions and depth plane of each screen triangle.
//
// Integer widths: snapped vertex coordinates are int32 within +-2^23
// subpixels (8 subpixel bits, guard band of raster_types.h), so edge steps
// a, b = coordinate differences fit in 25 bits and the edge constant c in
// 50 bits (int64). The tile stage evaluates edges in int64 per 8x8 block and
// in int32 inside a block, where only edges crossing the block remain and
// |value| <= 7(|a|+|b|) < 2^28.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/raster/clipper.h"
#include "engine/raster/raster_types.h"
#include "engine/raster/triangle_interp.h"

namespace cr {

// Inclusive pixel rectangle.
struct PixelRect {
  int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x0 > x1 || y0 > y1; }
};

inline PixelRect intersect(const PixelRect& a, const PixelRect& b) {
  return {a.x0 > b.x0 ? a.x0 : b.x0, a.y0 > b.y0 ? a.y0 : b.y0, a.x1 < b.x1 ? a.x1 : b.x1,
          a.y1 < b.y1 ? a.y1 : b.y1};
}

// One convex piece of a clipped triangle, in pixel units.
struct ScreenTriangle {
  // Pixel (x, y) is covered iff a[i]*x + b[i]*y + c[i] >= 0 for all three
  // edges. Pixel centres, subpixel scale and the top-left rule are folded into c.
  int32_t a[3];
  int32_t b[3];
  int64_t c[3];
  // Multisampling: 256 c plus the remainder, so that a sample offset
  // (dx, dy) subpixels from the centre has c = (c_num + a dx + b dy) >> 8
  // (exact); c_any is the largest such c over the offsets within the
  // setup's sample margin (conservative, for bounds and binning).
  int64_t c_num[3];
  int64_t c_any[3];
  // NDC depth at pixel (x, y): z0 + (zx * (x - ref_x) + zy * (y - ref_y)),
  // clamped to [z_min, z_max], the range over the piece's vertices.
  float z0, zx, zy;
  float z_min, z_max;
  int32_t ref_x, ref_y;
  uint32_t id;      // triangle id (of the original triangle)
  uint32_t interp;  // index of its TriangleInterp in the same SetupBatch
  bool alpha_mask;
  // Vertex extent <= kSmallExtent subpixels: every edge value over the
  // bounding box (plus a span's 7 extra lanes) fits in int32, no block descent needed.
  bool small;
};

// 64 pixels: |a|, |b| <= 2^14, so |edge value| <= 2^14 * 72 px * 2 < 2^22 over a small triangle's box.
inline constexpr int32_t kSmallExtent = 64 * kSubpixelScale;

// Largest edge value of edge e over the samples of the pixels of r (non-empty).
inline int64_t edge_max(const ScreenTriangle& t, int e, const PixelRect& r) {
  const int64_t a = t.a[e], b = t.b[e];
  return t.c_any[e] + a * (a > 0 ? r.x1 : r.x0) + b * (b > 0 ? r.y1 : r.y0);
}

// False when some edge excludes all samples of r: the triangle does not touch r.
inline bool may_cover(const ScreenTriangle& t, const PixelRect& r) {
  return edge_max(t, 0, r) >= 0 && edge_max(t, 1, r) >= 0 && edge_max(t, 2, r) >= 0;
}

enum class CullMode : uint8_t {
  Back,  // drop back faces of draws that are not double-sided
  None,  // keep both sides of everything
};

struct SetupParams {
  int width = 0;
  int height = 0;
  GuardBand band;
  CullMode cull = CullMode::Back;
  // Largest sample offset from the pixel centre (subpixels, either axis):
  // bounds cover every pixel one of whose samples the triangle may cover.
  int32_t sample_margin = 0;
};

// A vertex after the vertex stage. Snapping is done once per vertex, so
// triangles sharing it see identical coordinates.
inline constexpr uint32_t kNotFinite = 1u << 31;  // outcode bit: a non-finite coordinate
struct ProjectedVertex {
  glm::vec4 clip;
  int32_t x, y;      // snapped subpixel position (when outcode == 0)
  float z;           // NDC depth (when outcode == 0)
  uint32_t outcode;  // clip planes the vertex is outside of (clipper.h), or kNotFinite
};

ProjectedVertex project_vertex(const glm::vec4& clip, const SetupParams& params);

struct SetupCounters {
  uint64_t in = 0, culled = 0, clipped = 0, visible = 0, screen = 0;
};

// The set-up triangles of one contiguous range of input triangles, in input order.
struct SetupBatch {
  uint32_t id_base = 0;  // triangle id of interps[0]
  std::vector<TriangleInterp> interps;  // one per surviving original triangle
  std::vector<ScreenTriangle> triangles;
  std::vector<PixelRect> bounds;        // per screen triangle, clamped to the image
  SetupCounters counters;

  void clear(uint32_t first_id);
};

// Sets up triangle `triangle_index` of `draw` with vertices v0..v2 and
// appends what survives to `out` (its id is out.id_base + out.interps.size()).
void setup_triangle(const ProjectedVertex& v0, const ProjectedVertex& v1, const ProjectedVertex& v2,
                    const RasterDraw& draw, uint32_t triangle_index, const SetupParams& params, SetupBatch& out);

}  // namespace cr

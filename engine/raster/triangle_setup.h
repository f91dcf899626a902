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
#include <algorithm>
#include <cstdint>
#include <memory>
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
  // Pixel (x, y) is covered iff a[i]*x + b[i]*y + c(i) >= 0 for all three
  // edges. Pixel centres, subpixel scale and the top-left rule are folded into c.
  int32_t a[3];
  int32_t b[3];
  // 256 c plus the remainder, so that a sample offset (dx, dy) subpixels
  // from the centre has c = (c_num + a dx + b dy) >> 8 (exact).
  int64_t c_num[3];
  // Tiny triangles (below): the covered pixel centres of the piece's pixel
  // bounds, bit 8 j + i for pixel (x0 + i, y0 + j). Never 0: a tiny piece
  // that covers no pixel centre is not emitted.
  uint64_t mask;
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
  // One sample per pixel, small, and pixel bounds within kTinySize x
  // kTinySize: coverage decided at setup (mask), rasterised without edges.
  bool tiny;

  int64_t c(int e) const { return c_num[e] >> kSubpixelBits; }  // arithmetic shift: floor
};

// 64 pixels: |a|, |b| <= 2^14, so |edge value| <= 2^14 * 72 px * 2 < 2^22 over a small triangle's box.
inline constexpr int32_t kSmallExtent = 64 * kSubpixelScale;
// Largest pixel bounds (either axis) of a tiny triangle: one 8-pixel span per row.
inline constexpr int kTinySize = 8;

// Largest edge value of edge e over the samples of the pixels of r (non-empty),
// with samples up to `margin` subpixels from the pixel centres.
inline int64_t edge_max(const ScreenTriangle& t, int e, const PixelRect& r, int32_t margin) {
  const int64_t a = t.a[e], b = t.b[e];
  const int64_t c_any = (t.c_num[e] + ((a < 0 ? -a : a) + (b < 0 ? -b : b)) * margin) >> kSubpixelBits;
  return c_any + a * (a > 0 ? r.x1 : r.x0) + b * (b > 0 ? r.y1 : r.y0);
}

// False when some edge excludes all samples of r: the triangle does not touch r.
inline bool may_cover(const ScreenTriangle& t, const PixelRect& r, int32_t margin) {
  return edge_max(t, 0, r, margin) >= 0 && edge_max(t, 1, r, margin) >= 0 && edge_max(t, 2, r, margin) >= 0;
}

// A tiny triangle's mask limited to the pixels of r (within its bounds `b`).
inline uint64_t tiny_mask_within(uint64_t mask, const PixelRect& b, const PixelRect& r) {
  const unsigned cols = ((2u << (r.x1 - b.x0)) - 1) & ~((1u << (r.x0 - b.x0)) - 1);
  uint64_t rows = 0;
  for (int y = r.y0; y <= r.y1; ++y) rows |= uint64_t(cols) << (kTinySize * (y - b.y0));
  return mask & rows;
}

// A growable array that leaves new elements uninitialised (std::vector would
// write every element twice) and keeps its capacity across clear().
template <typename T>
class GrowBuffer {
 public:
  T& push_uninit() {
    if (size_ == capacity_) grow();
    return data_[size_++];
  }
  void pop_back() { --size_; }
  void clear() { size_ = 0; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  const T* begin() const { return data_.get(); }
  const T* end() const { return data_.get() + size_; }

 private:
  void grow() {
    const size_t capacity = capacity_ < 256 ? 256 : 2 * capacity_;
    std::unique_ptr<T[]> data = std::make_unique_for_overwrite<T[]>(capacity);
    std::copy_n(data_.get(), size_, data.get());
    data_ = std::move(data);
    capacity_ = capacity;
  }
  std::unique_ptr<T[]> data_;
  size_t size_ = 0, capacity_ = 0;
};

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
  double sx = 0.0, sy = 0.0;  // 2 / width and -2 / height: NDC per pixel
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

// project_vertex(model_to_clip * vec4(positions[i], 1)) into out[i] for i < count, eight
// at a time (lane-wise, the same IEEE operations as glm and project_vertex).
void project_vertices(const glm::vec3* positions, size_t count, const glm::mat4& model_to_clip,
                      const SetupParams& params, ProjectedVertex* out);

struct SetupCounters {
  uint64_t in = 0, culled = 0, clipped = 0, visible = 0, screen = 0;
};

// The set-up triangles of one contiguous range of input triangles, in input order.
struct SetupBatch {
  uint32_t id_base = 0;  // triangle id of interps[0]
  GrowBuffer<TriangleInterp> interps;   // one per surviving original triangle
  GrowBuffer<ScreenTriangle> triangles;  // the pieces that may cover a sample
  GrowBuffer<PixelRect> bounds;         // per screen triangle, clamped to the image
  SetupCounters counters;

  void clear(uint32_t first_id);
};

// Sets up triangle `triangle_index` of `draw` with vertices v0..v2 and
// appends what survives to `out` (its id is out.id_base + out.interps.size()).
// A tiny piece that covers no pixel centre is not emitted; when that leaves
// nothing of the triangle it still gets its id (and a slot in interps) but
// no interpolation planes: no output will ever name it.
void setup_triangle(const ProjectedVertex& v0, const ProjectedVertex& v1, const ProjectedVertex& v2,
                    const RasterDraw& draw, uint32_t triangle_index, const SetupParams& params, SetupBatch& out);

// setup_triangle for triangles first .. first + count - 1 of `draw`, whose
// projected vertices are vertices[0 .. vertex_count - 1], with the same
// results; the unclipped ones share their floating-point work in batches
// (lane-wise, the same IEEE operations). Throws on an index out of range.
void setup_triangles(const ProjectedVertex* vertices, size_t vertex_count, const RasterDraw& draw, uint32_t first,
                     uint32_t count, const SetupParams& params, SetupBatch& out);

}  // namespace cr

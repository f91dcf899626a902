#include "engine/raster/tile_raster.h"

#include "engine/raster/span8.h"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cstring>
#include <deque>
#include <vector>

namespace cr {

namespace {

using namespace span8;

constexpr int kBlock = 8;
// Tile-local rows are padded by one 8-pixel span so a span starting at any
// column of the tile can be loaded and stored whole.
constexpr int kRowPadding = kBlock;

struct TileScratch {
  std::vector<float> depth;
  std::vector<uint32_t> ids;
  std::vector<uint8_t> covered;  // multisampled blending: the current triangle's samples per pixel
};

// Per-thread tile buffers, reused across tiles and frames. A stack, because a
// callback that waits on the job system may run another tile on this thread.
class ScratchLease {
 public:
  ScratchLease() {
    if (pool_.size() <= depth_) pool_.emplace_back();
    scratch_ = &pool_[depth_++];
  }
  ~ScratchLease() { --depth_; }
  ScratchLease(const ScratchLease&) = delete;
  ScratchLease& operator=(const ScratchLease&) = delete;
  TileScratch& operator*() const { return *scratch_; }

 private:
  static thread_local std::deque<TileScratch> pool_;  // deque: growing keeps leased elements in place
  static thread_local size_t depth_;
  TileScratch* scratch_;
};
thread_local std::deque<TileScratch> ScratchLease::pool_;
thread_local size_t ScratchLease::depth_ = 0;

struct TileContext {
  float* depth;    // at the tile's origin (x0, y0)
  uint32_t* ids;
  int stride;
  int x0, y0;  // tile origin in the image
  // Largest first column of an 8-pixel span. Written straight into the
  // image, a span must stay within the tile: one that would start further
  // right starts here instead (its columns masked). A padded tile buffer
  // takes any span (INT_MAX).
  int span_end;
  const TileTarget* target;
  TileStats* stats;
  float sample_dx = 0.0f, sample_dy = 0.0f;  // the sample's offset from the pixel centre (alpha-mask coverage)
  // Multisampled blending: samples that pass set bit `sample_bit` here
  // (tile-local, as depth) instead of calling the fragment function.
  uint8_t* covered = nullptr;
  uint8_t sample_bit = 0;
};

// Lanes x .. x1 of a span starting at column xs (x >= xs).
unsigned span_columns(int xs, int x, int x1) {
  const int last = x1 - xs < kBlock - 1 ? x1 - xs : kBlock - 1;
  return ((2u << last) - 1) & ~((1u << (x - xs)) - 1);
}

// What one triangle needs while walking its pixels.
struct TriangleWalk {
  const ScreenTriangle& t;
  const TriangleInterp& interp;
  const TileContext& ctx;
  F z0, zx, zmin, zmax;
  I id;
  uint64_t covered = 0, passed = 0;

  TriangleWalk(const ScreenTriangle& tri, const TriangleInterp& ti, const TileContext& c)
      : t(tri), interp(ti), ctx(c), z0(fset1(t.z0)), zx(fset1(t.zx)), zmin(fset1(t.z_min)), zmax(fset1(t.z_max)),
        id(iset1(int32_t(t.id))) {}

  // Depth test and output of the covered samples (lanes of `cov`) of the
  // span of 8 pixels starting at (x, y).
  template <TileMode Mode>
  void shade(int x, int y, I cov) {
    const unsigned cov_bits = bits(cov);
    if (!cov_bits) return;
    covered += unsigned(std::popcount(cov_bits));
    float* zrow = ctx.depth + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0);
    const F zxfx = zx * to_float(iset1(x - t.ref_x) + lanes());
    const F zyfy = fset1(t.zy * float(y - t.ref_y));
    F z = min(max(z0 + (zxfx + zyfy), zmin), zmax);
    if (ctx.target->depth_format == DepthFormat::Unorm24) z = quantize_unorm24(z);
    if (ctx.target->depth_format == DepthFormat::Float24) z = quantize_float24(z);
    I pass = greater(z, load(zrow)) & cov;
    unsigned pass_bits = bits(pass);
    if (!pass_bits) return;

    const float py = float(y) + 0.5f + ctx.sample_dy;
    if constexpr (Mode == TileMode::Blended) {
      passed += unsigned(std::popcount(pass_bits));
      if (ctx.covered) {
        uint8_t* row = ctx.covered + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0);
        for (unsigned b = pass_bits; b; b &= b - 1) row[std::countr_zero(b)] |= ctx.sample_bit;
        return;
      }
      for (unsigned b = pass_bits; b; b &= b - 1) {
        const int px = x + std::countr_zero(b);
        (*ctx.target->fragment)(px, y, t.id, interpolate(interp, float(px) + 0.5f, py), 1.0f);
      }
    } else {
      if (t.alpha_mask) {
        for (unsigned b = pass_bits; b; b &= b - 1) {
          const int lane = std::countr_zero(b);
          if (!(*ctx.target->coverage)(t.id, interpolate(interp, float(x + lane) + 0.5f + ctx.sample_dx, py)))
            pass_bits &= ~(1u << lane);
        }
        if (!pass_bits) return;
        pass = from_bits(pass_bits);
      }
      passed += unsigned(std::popcount(pass_bits));
      store(zrow, z, pass, pass_bits);
      if constexpr (Mode == TileMode::Visibility)
        store(ctx.ids + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0), id, pass, pass_bits);
    }
  }
};

// A tiny triangle: its covered pixels are known (ScreenTriangle::mask), one
// span per row of its bounds b, here limited to r.
template <TileMode Mode>
void walk_tiny(TriangleWalk& w, const PixelRect& b, const PixelRect& r) {
  const uint64_t mask = w.t.mask;
  const int shift = r.x0 - b.x0;
  const unsigned cols = (2u << (r.x1 - r.x0)) - 1;
  const int xs = std::min(r.x0, w.ctx.span_end);
  for (int y = r.y0; y <= r.y1; ++y) {
    const unsigned row = unsigned(mask >> (kTinySize * (y - b.y0) + shift)) & cols;
    if (row) w.template shade<Mode>(xs, y, from_bits(row << (r.x0 - xs)));
  }
}

// A small triangle: all edge values over its box (and 7 pixels either side)
// fit in int32, so its rows are scanned directly, 8 pixels at a time.
template <TileMode Mode>
void walk_small(TriangleWalk& w, const PixelRect& r) {
  const ScreenTriangle& t = w.t;
  const I astep[3] = {steps(t.a[0]), steps(t.a[1]), steps(t.a[2])};
  int32_t row[3];
  for (int e = 0; e < 3; ++e) row[e] = int32_t(t.c(e) + int64_t(t.a[e]) * r.x0 + int64_t(t.b[e]) * r.y0);
  // The last span of each row: where it starts and its columns.
  const int last_x = r.x0 + (r.x1 - r.x0) / kBlock * kBlock;
  const int last_xs = std::min(last_x, w.ctx.span_end);
  const I last_cols = from_bits(span_columns(last_xs, last_x, r.x1));
  const I all = iset1(-1);
  for (int y = r.y0; y <= r.y1; ++y) {
    int32_t f[3] = {row[0], row[1], row[2]};
    for (int x = r.x0; x < last_x; x += kBlock) {
      const I any = (iset1(f[0]) + astep[0]) | (iset1(f[1]) + astep[1]) | (iset1(f[2]) + astep[2]);
      w.template shade<Mode>(x, y, andnot(sign(any), all));  // covered where no edge value is negative
      for (int e = 0; e < 3; ++e) f[e] += kBlock * t.a[e];
    }
    const int d = last_x - last_xs;
    const I any = (iset1(f[0] - d * t.a[0]) + astep[0]) | (iset1(f[1] - d * t.a[1]) + astep[1]) |
                  (iset1(f[2] - d * t.a[2]) + astep[2]);
    w.template shade<Mode>(last_xs, y, andnot(sign(any), last_cols));
    for (int e = 0; e < 3; ++e) row[e] += t.b[e];
  }
}

// A large triangle: 8x8 blocks, each classifying the edges in int64 at its
// corners; rejected blocks are skipped, edges that contain the whole block
// are dropped (a block inside all three needs no edge test at all), and only
// crossing edges are evaluated, in int32 (a crossing edge has
// |value| <= 7(|a| + |b|) < 2^28 in the block, 7 |a| more where the span is
// moved left to stay in the tile).
template <TileMode Mode>
void walk_blocks(TriangleWalk& w, const PixelRect& r) {
  const ScreenTriangle& t = w.t;
  const I astep[3] = {steps(t.a[0]), steps(t.a[1]), steps(t.a[2])};
  for (int by = r.y0; by <= r.y1; by += kBlock) {
    const int bh = std::min(kBlock, r.y1 - by + 1);
    for (int bx = r.x0; bx <= r.x1; bx += kBlock) {
      const int bw = std::min(kBlock, r.x1 - bx + 1);
      const int xs = std::min(bx, w.ctx.span_end);
      int32_t f[3], b[3];
      I step[3];
      int n = 0;
      bool rejected = false;
      for (int e = 0; e < 3; ++e) {
        const int64_t fe = t.c(e) + int64_t(t.a[e]) * bx + int64_t(t.b[e]) * by;
        const int64_t dx = int64_t(t.a[e]) * (bw - 1), dy = int64_t(t.b[e]) * (bh - 1);
        if (fe + std::max<int64_t>(dx, 0) + std::max<int64_t>(dy, 0) < 0) {
          rejected = true;
          break;
        }
        if (fe + std::min<int64_t>(dx, 0) + std::min<int64_t>(dy, 0) >= 0) continue;  // whole block inside
        f[n] = int32_t(fe - int64_t(t.a[e]) * (bx - xs));
        b[n] = t.b[e];
        step[n++] = astep[e];
      }
      if (rejected) continue;
      const I cols = from_bits(span_columns(xs, bx, bx + bw - 1));
      for (int j = 0; j < bh; ++j) {
        I any = iset1(0);
        for (int k = 0; k < n; ++k) any = any | (iset1(f[k]) + step[k]);
        w.template shade<Mode>(xs, by + j, andnot(sign(any), cols));
        for (int k = 0; k < n; ++k) f[k] += b[k];
      }
    }
  }
}

template <TileMode Mode>
void walk(TriangleWalk& w, const PixelRect& b, const PixelRect& r) {
  if (w.t.tiny)
    walk_tiny<Mode>(w, b, r);
  else if (w.t.small)
    walk_small<Mode>(w, r);
  else
    walk_blocks<Mode>(w, r);
  w.ctx.stats->pixels_covered += w.covered;
  w.ctx.stats->pixels_passed += w.passed;
}

// The triangle as sample s of the pattern sees it at the pixel centres:
// edge constants and depth plane moved by the sample's offset.
ScreenTriangle at_sample(const ScreenTriangle& t, const SamplePattern& pattern, int s) {
  ScreenTriangle ts = t;
  const int64_t dx = pattern.dx_subpixels(s), dy = pattern.dy_subpixels(s);
  for (int e = 0; e < 3; ++e) ts.c_num[e] = t.c_num[e] + t.a[e] * dx + t.b[e] * dy;  // c(e): the same shift
  ts.z0 = t.z0 + (t.zx * pattern.dx(s) + t.zy * pattern.dy(s));
  return ts;
}

// Resolves a multisampled tile's layers into the image (see tile_raster.h):
// per row, a branch-free pass (it vectorises) for the ids, the mean depths
// and which pixels are mixed, then the mixed ones listed.
void resolve_samples(const TileScratch& scratch, size_t layer, int stride, const PixelRect& rect,
                     const TileTarget& target) {
  const int n = target.pattern.count;
  const float inv_n = 1.0f / float(n);
  MixedSamples& mixed = *target.mixed;
  mixed.clear();
  const uint32_t* __restrict ids = scratch.ids.data();
  const float* __restrict depth = scratch.depth.data();
  const int w = rect.x1 - rect.x0 + 1;
  uint8_t differs[256];
  for (int y = 0; y <= rect.y1 - rect.y0; ++y) {
    const size_t in = size_t(y) * size_t(stride);
    const size_t out = size_t(rect.y0 + y) * size_t(target.stride) + size_t(rect.x0);
    uint32_t* __restrict out_ids = target.ids + out;
    float* __restrict out_depth = target.depth + out;
    for (int x = 0; x < w; ++x) {
      const uint32_t first = ids[in + size_t(x)];
      uint8_t d = 0;
      float z = depth[in + size_t(x)];
      for (int s = 1; s < n; ++s) {
        d |= ids[size_t(s) * layer + in + size_t(x)] != first;
        z += depth[size_t(s) * layer + in + size_t(x)];
      }
      differs[x] = d;
      out_ids[x] = first;
      out_depth[x] = d ? depth[in + size_t(x)] : z * inv_n;
    }
    for (int x = 0; x < w; ++x) {
      if (!differs[x]) continue;
      mixed.pixels.push_back(uint32_t(out + size_t(x)));
      for (int s = 0; s < n; ++s) {
        mixed.triangle.push_back(ids[size_t(s) * layer + in + size_t(x)]);
        mixed.depth.push_back(depth[size_t(s) * layer + in + size_t(x)]);
      }
    }
  }
}

// Multisampled blending: the triangle's fragments, one per pixel that some
// sample of it passed, in row-major order, at the centroid of those samples
// with their share as coverage; the pixels' sample bits are cleared again.
void deliver_coverage(const ScreenTriangle& t, const TriangleInterp& interp, const PixelRect& r,
                      const TileContext& ctx) {
  const SamplePattern& pattern = ctx.target->pattern;
  for (int y = r.y0; y <= r.y1; ++y) {
    uint8_t* row = ctx.covered + size_t(y - ctx.y0) * ctx.stride;
    for (int x = r.x0; x <= r.x1; ++x) {
      const unsigned bits = row[x - ctx.x0];
      if (!bits) continue;
      row[x - ctx.x0] = 0;
      float dx = 0.0f, dy = 0.0f;
      for (int s = 0; s < pattern.count; ++s)
        if (bits & (1u << s)) {
          dx += pattern.dx(s);
          dy += pattern.dy(s);
        }
      const float n = float(std::popcount(bits));
      (*ctx.target->fragment)(x, y, t.id,
                              interpolate(interp, float(x) + 0.5f + dx / n, float(y) + 0.5f + dy / n),
                              n / float(pattern.count));
    }
  }
}

template <TileMode Mode>
void raster_triangles(const PixelRect& tile_rect, std::span<const GeometryChunk> chunks, int tile,
                      const TileContext& ctx, size_t layer) {
  const SamplePattern& pattern = ctx.target->pattern;
  for (const GeometryChunk& chunk : chunks) {
    const SetupBatch& setup = chunk.setup;
    const uint32_t end = chunk.bins.begin[tile + 1];
    for (uint32_t i = chunk.bins.begin[tile]; i < end; ++i) {
      const uint32_t k = chunk.bins.items[i];
      const ScreenTriangle& t = setup.triangles[k];
      const PixelRect& b = setup.bounds[k];
      const PixelRect r = intersect(b, tile_rect);
      ctx.stats->triangles += 1;
      if (pattern.count == 1) {
        TriangleWalk w(t, setup.interps[t.interp], ctx);
        walk<Mode>(w, b, r);
        continue;
      }
      for (int s = 0; s < pattern.count; ++s) {
        const ScreenTriangle ts = at_sample(t, pattern, s);
        TileContext sample_ctx = ctx;
        if constexpr (Mode == TileMode::Blended) {
          sample_ctx.sample_bit = uint8_t(1u << s);  // one opaque depth per pixel: no layer
        } else {
          sample_ctx.depth += size_t(s) * layer;
          sample_ctx.ids += size_t(s) * layer;
        }
        sample_ctx.sample_dx = pattern.dx(s);
        sample_ctx.sample_dy = pattern.dy(s);
        TriangleWalk w(ts, setup.interps[t.interp], sample_ctx);
        walk<Mode>(w, b, r);
      }
      if constexpr (Mode == TileMode::Blended) deliver_coverage(t, setup.interps[t.interp], r, ctx);
    }
  }
}

}  // namespace

void raster_tile(int tile, const TileGrid& grid, std::span<const GeometryChunk> chunks, const TileTarget& target,
                 TileStats& stats) {
  // A tile no triangle touches: nothing drawn, without clearing and copying
  // a tile buffer per sample.
  bool empty = true;
  for (const GeometryChunk& chunk : chunks) empty &= chunk.bins.begin[tile] == chunk.bins.begin[tile + 1];
  if (empty) {
    stats = {};
    if (target.mode == TileMode::Blended) return;
    const PixelRect r = grid.tile_rect(tile);
    for (int y = r.y0; y <= r.y1; ++y) {
      const size_t out = size_t(y) * target.stride + size_t(r.x0);
      std::fill_n(target.depth + out, r.x1 - r.x0 + 1, 0.0f);
      if (target.mode == TileMode::Visibility) std::fill_n(target.ids + out, r.x1 - r.x0 + 1, kNoTriangle);
    }
    if (target.mixed) target.mixed->clear();
    return;
  }
  const PixelRect rect = grid.tile_rect(tile);
  const int w = rect.x1 - rect.x0 + 1, h = rect.y1 - rect.y0 + 1;
  stats = {};
  // One sample per pixel and a tile at least a span wide: straight into the
  // image (cleared here, while the tile's rows are brought into cache).
  if (target.pattern.count == 1 && w >= kBlock) {
    const size_t origin = size_t(rect.y0) * target.stride + size_t(rect.x0);
    // Blended: the opaque depth, only read.
    float* depth = target.mode == TileMode::Blended ? const_cast<float*>(target.opaque_depth) : target.depth;
    TileContext ctx{depth + origin, target.ids ? target.ids + origin : nullptr, target.stride, rect.x0, rect.y0,
                    rect.x1 - (kBlock - 1), &target, &stats};
    switch (target.mode) {
      case TileMode::Visibility:
        for (int y = 0; y < h; ++y) {
          std::fill_n(ctx.depth + size_t(y) * target.stride, w, 0.0f);  // reversed-Z: 0 is infinitely far
          std::fill_n(ctx.ids + size_t(y) * target.stride, w, kNoTriangle);
        }
        raster_triangles<TileMode::Visibility>(rect, chunks, tile, ctx, 0);
        break;
      case TileMode::Depth:
        for (int y = 0; y < h; ++y) std::fill_n(ctx.depth + size_t(y) * target.stride, w, 0.0f);
        raster_triangles<TileMode::Depth>(rect, chunks, tile, ctx, 0);
        break;
      case TileMode::Blended:
        raster_triangles<TileMode::Blended>(rect, chunks, tile, ctx, 0);
        break;
    }
    if (target.mixed) target.mixed->clear();
    return;
  }

  // Otherwise a tile buffer with padded rows, one layer per sample.
  const ScratchLease lease;
  TileScratch& scratch = *lease;
  const int stride = grid.tile_size + kRowPadding;
  const size_t layer = size_t(stride) * grid.tile_size;
  const int samples = target.mode == TileMode::Visibility ? target.pattern.count : 1;
  const size_t size = layer * size_t(samples);
  if (scratch.depth.size() < size) {
    scratch.depth.resize(size);
    scratch.ids.resize(size);
  }
  if (target.mode == TileMode::Blended && target.pattern.count > 1 && scratch.covered.size() < layer)
    scratch.covered.assign(layer, 0);  // every walk leaves it cleared
  if (target.mode == TileMode::Blended) {
    for (int y = 0; y < h; ++y)
      std::memcpy(&scratch.depth[size_t(y) * stride],
                  target.opaque_depth + size_t(rect.y0 + y) * target.stride + rect.x0, sizeof(float) * w);
  } else {
    std::fill_n(scratch.depth.begin(), size, 0.0f);  // reversed-Z: 0 is infinitely far
    std::fill_n(scratch.ids.begin(), size, kNoTriangle);
  }

  TileContext ctx{scratch.depth.data(), scratch.ids.data(), stride, rect.x0, rect.y0, INT_MAX, &target, &stats};
  if (target.mode == TileMode::Blended && target.pattern.count > 1) ctx.covered = scratch.covered.data();
  switch (target.mode) {
    case TileMode::Visibility: raster_triangles<TileMode::Visibility>(rect, chunks, tile, ctx, layer); break;
    case TileMode::Depth: raster_triangles<TileMode::Depth>(rect, chunks, tile, ctx, layer); break;
    case TileMode::Blended: raster_triangles<TileMode::Blended>(rect, chunks, tile, ctx, layer); break;
  }

  if (target.mode == TileMode::Blended) return;
  if (samples > 1) {
    resolve_samples(scratch, layer, stride, rect, target);
    return;
  }
  for (int y = 0; y < h; ++y) {
    const size_t out = size_t(rect.y0 + y) * target.stride + rect.x0;
    std::memcpy(target.depth + out, &scratch.depth[size_t(y) * stride], sizeof(float) * w);
    if (target.mode == TileMode::Visibility)
      std::memcpy(target.ids + out, &scratch.ids[size_t(y) * stride], sizeof(uint32_t) * w);
  }
}

}  // namespace cr

#include "engine/raster/tile_raster.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <deque>
#include <vector>

namespace cr {

namespace {

constexpr int kBlock = 8;
// Tile-local rows are padded by one 8-pixel span so a span starting at any
// column of the tile can be loaded and stored whole.
constexpr int kRowPadding = kBlock;

// Set bits of an 8-bit span mask (the SSE2 baseline has no popcnt instruction).
constexpr auto kBitCount = [] {
  std::array<uint8_t, 256> t{};
  for (int i = 1; i < 256; ++i) t[i] = uint8_t((i & 1) + t[i >> 1]);
  return t;
}();

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
  float* depth;
  uint32_t* ids;
  int stride;
  int x0, y0;  // tile origin in the image
  const TileTarget* target;
  TileStats* stats;
  float sample_dx = 0.0f, sample_dy = 0.0f;  // the sample's offset from the pixel centre (alpha-mask coverage)
  // Multisampled blending: samples that pass set bit `sample_bit` here
  // (tile-local, as depth) instead of calling the fragment function.
  uint8_t* covered = nullptr;
  uint8_t sample_bit = 0;
};

int mask_of(__m128i lo, __m128i hi) {
  return _mm_movemask_ps(_mm_castsi128_ps(lo)) | (_mm_movemask_ps(_mm_castsi128_ps(hi)) << 4);
}

__m128i select(__m128i mask, __m128i a, __m128i b) {
  return _mm_or_si128(_mm_and_si128(mask, a), _mm_andnot_si128(mask, b));
}

__m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

// What one triangle needs while walking its pixels.
struct TriangleWalk {
  const ScreenTriangle& t;
  const TriangleInterp& interp;
  const TileContext& ctx;
  __m128i astep_lo[3], astep_hi[3];  // a * lane for lanes 0..7 of a span
  __m128 z0, zx, zmin, zmax;
  __m128i id;
  uint64_t covered = 0, passed = 0;

  TriangleWalk(const ScreenTriangle& tri, const TriangleInterp& ti, const TileContext& c) : t(tri), interp(ti), ctx(c) {
    for (int e = 0; e < 3; ++e) {
      const int32_t a = t.a[e];
      astep_lo[e] = _mm_setr_epi32(0, a, 2 * a, 3 * a);
      astep_hi[e] = _mm_setr_epi32(4 * a, 5 * a, 6 * a, 7 * a);
    }
    z0 = _mm_set1_ps(t.z0);
    zx = _mm_set1_ps(t.zx);
    zmin = _mm_set1_ps(t.z_min);
    zmax = _mm_set1_ps(t.z_max);
    id = _mm_set1_epi32(int32_t(t.id));
  }

  // Coverage of the 8-pixel span starting at column x from the edge values
  // f[k] at x of the edges live[0..n-1], limited to the first `width` lanes.
  void coverage(const int32_t* f, const int* live, int n, __m128i cols_lo, __m128i cols_hi, __m128i& cov_lo,
                __m128i& cov_hi) const {
    __m128i any_lo = _mm_setzero_si128(), any_hi = _mm_setzero_si128();
    for (int k = 0; k < n; ++k) {
      const __m128i base = _mm_set1_epi32(f[k]);
      any_lo = _mm_or_si128(any_lo, _mm_add_epi32(base, astep_lo[live[k]]));
      any_hi = _mm_or_si128(any_hi, _mm_add_epi32(base, astep_hi[live[k]]));
    }
    // Covered where no edge value is negative (sign bit of the OR clear).
    cov_lo = _mm_andnot_si128(_mm_srai_epi32(any_lo, 31), cols_lo);
    cov_hi = _mm_andnot_si128(_mm_srai_epi32(any_hi, 31), cols_hi);
  }

  // Depth test and output of the covered samples of the span at (x, y).
  template <TileMode Mode>
  void shade(int x, int y, __m128i cov_lo, __m128i cov_hi) {
    const int cov = mask_of(cov_lo, cov_hi);
    if (!cov) return;
    covered += kBitCount[cov];
    float* zrow = ctx.depth + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0);
    const __m128i fx = _mm_set1_epi32(x - t.ref_x);
    const __m128 zyfy = _mm_set1_ps(t.zy * float(y - t.ref_y));
    const __m128 zxfx_lo = _mm_mul_ps(zx, _mm_cvtepi32_ps(_mm_add_epi32(fx, _mm_setr_epi32(0, 1, 2, 3))));
    const __m128 zxfx_hi = _mm_mul_ps(zx, _mm_cvtepi32_ps(_mm_add_epi32(fx, _mm_setr_epi32(4, 5, 6, 7))));
    const __m128 z_lo = _mm_min_ps(_mm_max_ps(_mm_add_ps(z0, _mm_add_ps(zxfx_lo, zyfy)), zmin), zmax);
    const __m128 z_hi = _mm_min_ps(_mm_max_ps(_mm_add_ps(z0, _mm_add_ps(zxfx_hi, zyfy)), zmin), zmax);
    const __m128 zb_lo = _mm_loadu_ps(zrow), zb_hi = _mm_loadu_ps(zrow + 4);
    __m128i pass_lo = _mm_and_si128(_mm_castps_si128(_mm_cmpgt_ps(z_lo, zb_lo)), cov_lo);
    __m128i pass_hi = _mm_and_si128(_mm_castps_si128(_mm_cmpgt_ps(z_hi, zb_hi)), cov_hi);
    int pass = mask_of(pass_lo, pass_hi);
    if (!pass) return;

    const float py = float(y) + 0.5f + ctx.sample_dy;
    if constexpr (Mode == TileMode::Blended) {
      passed += kBitCount[pass];
      if (ctx.covered) {
        uint8_t* row = ctx.covered + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0);
        for (int bits = pass; bits; bits &= bits - 1) row[std::countr_zero(unsigned(bits))] |= ctx.sample_bit;
        return;
      }
      for (int bits = pass; bits; bits &= bits - 1) {
        const int px = x + std::countr_zero(unsigned(bits));
        (*ctx.target->fragment)(px, y, t.id, interpolate(interp, float(px) + 0.5f, py), 1.0f);
      }
    } else {
      if (t.alpha_mask) {
        for (int bits = pass; bits; bits &= bits - 1) {
          const int lane = std::countr_zero(unsigned(bits));
          if (!(*ctx.target->coverage)(t.id, interpolate(interp, float(x + lane) + 0.5f + ctx.sample_dx, py)))
            pass &= ~(1 << lane);
        }
        if (!pass) return;
        const __m128i p = _mm_set1_epi32(pass);
        const __m128i bit_lo = _mm_setr_epi32(1, 2, 4, 8), bit_hi = _mm_setr_epi32(16, 32, 64, 128);
        pass_lo = _mm_cmpeq_epi32(_mm_and_si128(p, bit_lo), bit_lo);
        pass_hi = _mm_cmpeq_epi32(_mm_and_si128(p, bit_hi), bit_hi);
      }
      passed += kBitCount[pass];
      _mm_storeu_ps(zrow, select(_mm_castsi128_ps(pass_lo), z_lo, zb_lo));
      _mm_storeu_ps(zrow + 4, select(_mm_castsi128_ps(pass_hi), z_hi, zb_hi));
      if constexpr (Mode == TileMode::Visibility) {
        uint32_t* irow = ctx.ids + size_t(y - ctx.y0) * ctx.stride + (x - ctx.x0);
        const __m128i ib_lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(irow));
        const __m128i ib_hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(irow + 4));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(irow), select(pass_lo, id, ib_lo));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(irow + 4), select(pass_hi, id, ib_hi));
      }
    }
  }
};

// Lanes 0..width-1 of a span.
void span_columns(int width, __m128i& lo, __m128i& hi) {
  const __m128i w = _mm_set1_epi32(width);
  lo = _mm_cmplt_epi32(_mm_setr_epi32(0, 1, 2, 3), w);
  hi = _mm_cmplt_epi32(_mm_setr_epi32(4, 5, 6, 7), w);
}

// A small triangle: all edge values over its box fit in int32, so its rows
// are scanned directly, 8 pixels at a time.
template <TileMode Mode>
void walk_small(TriangleWalk& w, const PixelRect& r) {
  const ScreenTriangle& t = w.t;
  const int live[3] = {0, 1, 2};
  int32_t row[3];
  for (int e = 0; e < 3; ++e) row[e] = int32_t(t.c(e) + int64_t(t.a[e]) * r.x0 + int64_t(t.b[e]) * r.y0);
  // Column masks: full spans, then the last span of each row.
  const __m128i all = _mm_set1_epi32(-1);
  __m128i last_lo, last_hi;
  span_columns((r.x1 - r.x0) % kBlock + 1, last_lo, last_hi);
  for (int y = r.y0; y <= r.y1; ++y) {
    int32_t f[3] = {row[0], row[1], row[2]};
    for (int x = r.x0; x <= r.x1; x += kBlock) {
      const bool last = x + kBlock > r.x1;
      __m128i cov_lo, cov_hi;
      w.coverage(f, live, 3, last ? last_lo : all, last ? last_hi : all, cov_lo, cov_hi);
      w.template shade<Mode>(x, y, cov_lo, cov_hi);
      for (int e = 0; e < 3; ++e) f[e] += kBlock * t.a[e];
    }
    for (int e = 0; e < 3; ++e) row[e] += t.b[e];
  }
}

// A large triangle: 8x8 blocks, each classifying the edges in int64 at its
// corners; rejected blocks are skipped and only crossing edges are evaluated,
// in int32 (a crossing edge has |value| <= 7(|a| + |b|) < 2^28 in the block).
template <TileMode Mode>
void walk_blocks(TriangleWalk& w, const PixelRect& r) {
  const ScreenTriangle& t = w.t;
  for (int by = r.y0; by <= r.y1; by += kBlock) {
    const int bh = std::min(kBlock, r.y1 - by + 1);
    for (int bx = r.x0; bx <= r.x1; bx += kBlock) {
      const int bw = std::min(kBlock, r.x1 - bx + 1);
      int32_t f[3], b[3];
      int live[3];
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
        f[n] = int32_t(fe);
        b[n] = t.b[e];
        live[n++] = e;
      }
      if (rejected) continue;
      __m128i cols_lo, cols_hi, cov_lo, cov_hi;
      span_columns(bw, cols_lo, cols_hi);
      for (int j = 0; j < bh; ++j) {
        w.coverage(f, live, n, cols_lo, cols_hi, cov_lo, cov_hi);
        w.template shade<Mode>(bx, by + j, cov_lo, cov_hi);
        for (int k = 0; k < n; ++k) f[k] += b[k];
      }
    }
  }
}

// A tiny triangle: its covered pixels are known (ScreenTriangle::mask), one
// span per row of its bounds b, here limited to r.
template <TileMode Mode>
void walk_tiny(TriangleWalk& w, const PixelRect& b, const PixelRect& r) {
  const uint64_t mask = w.t.mask;
  const int shift = r.x0 - b.x0;
  const unsigned cols = (2u << (r.x1 - r.x0)) - 1;
  const __m128i bit_lo = _mm_setr_epi32(1, 2, 4, 8), bit_hi = _mm_setr_epi32(16, 32, 64, 128);
  for (int y = r.y0; y <= r.y1; ++y) {
    const unsigned bits = unsigned(mask >> (kTinySize * (y - b.y0) + shift)) & cols;
    if (!bits) continue;
    const __m128i m = _mm_set1_epi32(int(bits));
    w.template shade<Mode>(r.x0, y, _mm_cmpeq_epi32(_mm_and_si128(m, bit_lo), bit_lo),
                           _mm_cmpeq_epi32(_mm_and_si128(m, bit_hi), bit_hi));
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
  const ScratchLease lease;
  TileScratch& scratch = *lease;
  const PixelRect rect = grid.tile_rect(tile);
  const int w = rect.x1 - rect.x0 + 1, h = rect.y1 - rect.y0 + 1;
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

  stats = {};
  TileContext ctx{scratch.depth.data(), scratch.ids.data(), stride, rect.x0, rect.y0, &target, &stats};
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

// fog.filter: HDRP's 3x3 Gaussian (sigma = 1 froxel) within each slice. The
// kernel exp(-(dx^2 + dy^2) / 2) is separable, so it runs as a horizontal then
// a vertical 3-tap pass; edge taps are clamped to the grid like HDRP's
// clamped loads. With column-major storage each tap is a whole column, so the
// inner loop runs over contiguous slices (flat floats, vectorised).
//
// Depth culling: the vertical pass produces a column's active slices from
// the horizontal results of the column and its vertical neighbours, so the
// horizontal pass produces, per column, the most active slices of its
// vertical 3-neighbourhood; its taps are then within the lit slices of the
// horizontal neighbours (lit = active dilated by one column).
//
// q15 codes (sun_term_format.h) take the same kernel as integer weights that
// sum to 32768 exactly, so a neighbourhood of one value keeps it (fully lit
// air stays 32767) and the result never leaves [0, 32767]; one rounding, half up.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fog/froxel_passes.h"

namespace cr {

namespace {

// The 3-tap kernel: the middle tap's weight and each side tap's.
struct Kernel {
  float side = std::exp(-0.5f);
  float norm = 1.0f / (1.0f + 2.0f * side);
};

// (c + (a + b) side) norm.
struct FloatTaps {
  Kernel k;
  float operator()(float a, float c, float b) const { return (c + (a + b) * k.side) * k.norm; }
};

// The kernel in 1/32768ths: round(side norm 32768) per side tap, the rest in the middle.
struct Q15Taps {
  int32_t side = int32_t(std::lround(Kernel{}.side * Kernel{}.norm * 32768.0f));
  int32_t middle = 32768 - 2 * side;
  uint16_t operator()(uint16_t a, uint16_t c, uint16_t b) const {
    return uint16_t((int32_t(c) * middle + (int32_t(a) + int32_t(b)) * side + 0x4000) >> 15);
  }
};

template <class Taps, class V>
void filter_axis(const FroxelView& view, const std::vector<V>& in, bool horizontal, JobSystem& jobs,
                 std::vector<V>& out) {
  const FroxelGrid& g = view.grid;
  const Taps taps;
  const int nx = g.nx(), ny = g.ny();
  const uint16_t* active = view.active_slices.data();
  const V* src = in.data();
  V* dst_all = out.data();
  jobs.parallel_for(horizontal ? "fog.filter.x" : "fog.filter.y", size_t(ny), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        const int xa = horizontal ? std::max(x - 1, 0) : x, xb = horizontal ? std::min(x + 1, nx - 1) : x;
        const int ya = horizontal ? y : std::max(y - 1, 0), yb = horizontal ? y : std::min(y + 1, ny - 1);
        int n = active[size_t(y) * nx + x];
        if (horizontal)
          n = std::max({n, int(active[size_t(std::max(y - 1, 0)) * nx + x]),
                        int(active[size_t(std::min(y + 1, ny - 1)) * nx + x])});
        const V* a = src + g.index(xa, ya, 0);
        const V* c = src + g.index(x, y, 0);
        const V* b = src + g.index(xb, yb, 0);
        V* o = dst_all + g.index(x, y, 0);
        const size_t len = size_t(n);
        for (size_t j = 0; j < len; ++j) o[j] = taps(a[j], c[j], b[j]);
      }
  });
}

template <class Taps, class V>
void filter_both_axes(const FroxelView& view, const std::vector<V>& in, JobSystem& jobs, std::vector<V>& scratch,
                      std::vector<V>& out) {
  scratch.resize(view.grid.count());
  out.resize(view.grid.count());
  filter_axis<Taps>(view, in, true, jobs, scratch);
  filter_axis<Taps>(view, scratch, false, jobs, out);
}

}  // namespace

void filter_slices(const FroxelView& view, const std::vector<float>& in, JobSystem& jobs, std::vector<float>& scratch,
                   std::vector<float>& out) {
  filter_both_axes<FloatTaps>(view, in, jobs, scratch, out);
}

void filter_slices(const FroxelView& view, const std::vector<uint16_t>& in, JobSystem& jobs,
                   std::vector<uint16_t>& scratch, std::vector<uint16_t>& out) {
  filter_both_axes<Q15Taps>(view, in, jobs, scratch, out);
}

}  // namespace cr

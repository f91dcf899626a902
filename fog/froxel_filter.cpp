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
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"

namespace cr {

namespace {

void filter_axis(const FroxelView& view, const std::vector<float>& in, bool horizontal, JobSystem& jobs,
                 std::vector<float>& out) {
  const FroxelGrid& g = view.grid;
  const float side = std::exp(-0.5f);
  const float norm = 1.0f / (1.0f + 2.0f * side);
  const int nx = g.nx(), ny = g.ny();
  const uint16_t* active = view.active_slices.data();
  const float* src = in.data();
  float* dst_all = out.data();
  jobs.parallel_for(horizontal ? "fog.filter.x" : "fog.filter.y", size_t(ny), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        const int xa = horizontal ? std::max(x - 1, 0) : x, xb = horizontal ? std::min(x + 1, nx - 1) : x;
        const int ya = horizontal ? y : std::max(y - 1, 0), yb = horizontal ? y : std::min(y + 1, ny - 1);
        int n = active[size_t(y) * nx + x];
        if (horizontal)
          n = std::max({n, int(active[size_t(std::max(y - 1, 0)) * nx + x]),
                        int(active[size_t(std::min(y + 1, ny - 1)) * nx + x])});
        const float* a = src + g.index(xa, ya, 0);
        const float* c = src + g.index(x, y, 0);
        const float* b = src + g.index(xb, yb, 0);
        float* o = dst_all + g.index(x, y, 0);
        const size_t len = size_t(n);
        for (size_t j = 0; j < len; ++j) o[j] = (c[j] + (a[j] + b[j]) * side) * norm;
      }
  });
}

}  // namespace

void filter_slices(const FroxelView& view, const std::vector<float>& in, JobSystem& jobs, std::vector<float>& scratch,
                   std::vector<float>& out) {
  scratch.resize(view.grid.count());
  out.resize(view.grid.count());
  filter_axis(view, in, true, jobs, scratch);
  filter_axis(view, scratch, false, jobs, out);
}

}  // namespace cr

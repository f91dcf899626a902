// Depth-aware froxel culling: per column, the slices any pixel can read.
#include <algorithm>

#include <xmmintrin.h>

#include "fog/froxel_passes.h"

namespace cr {

namespace {

// out[c] = max of in over the 3x3 columns around c (clamped at the edges).
void dilate_3x3(const FroxelGrid& g, const std::vector<uint16_t>& in, JobSystem& jobs, std::vector<uint16_t>& out) {
  const int nx = g.nx(), ny = g.ny();
  out.resize(in.size());
  jobs.parallel_for("fog.cull.dilate", size_t(ny), 8, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        uint16_t m = 0;
        for (int yy = std::max(y - 1, 0); yy <= std::min(y + 1, ny - 1); ++yy)
          for (int xx = std::max(x - 1, 0); xx <= std::min(x + 1, nx - 1); ++xx)
            m = std::max(m, in[size_t(yy) * nx + xx]);
        out[size_t(y) * nx + x] = m;
      }
  });
}

}  // namespace

void cull_froxels_by_depth(FroxelView& view, const std::vector<float>& distance, JobSystem& jobs) {
  const FroxelGrid& g = view.grid;
  const int w = g.width(), h = g.height(), s = g.froxel_size(), nx = g.nx();
  if (distance.size() != size_t(w) * size_t(h)) return;  // no depth: keep every slice
  std::vector<uint16_t> needed(g.columns());
  jobs.parallel_for("fog.cull.tiles", size_t(g.ny()), 4, [&](size_t begin, size_t end) {
    for (int ty = int(begin); ty < int(end); ++ty)
      for (int tx = 0; tx < nx; ++tx) {
        // NaN distances are never composited: the comparison skips them.
        // Four running maxima with SSE (max_ps(a, b) is "a > b ? a : b",
        // NaN in a gives b): a max is exact in any order, and the only pair
        // an order could pick differently, +0 and -0, fails "> near" alike.
        __m128 lanes = _mm_setzero_ps();
        float farthest = 0.0f;
        const int xa = tx * s, xb = std::min((tx + 1) * s, w);
        for (int y = ty * s; y < std::min((ty + 1) * s, h); ++y) {
          const float* row = distance.data() + size_t(y) * w;
          int x = xa;
          for (; x + 4 <= xb; x += 4) lanes = _mm_max_ps(_mm_loadu_ps(row + x), lanes);
          for (; x < xb; ++x) farthest = row[x] > farthest ? row[x] : farthest;
        }
        alignas(16) float lane[4];
        _mm_store_ps(lane, lanes);
        for (float v : lane) farthest = v > farthest ? v : farthest;
        needed[size_t(ty) * nx + tx] =
            farthest > g.near_distance() ? uint16_t(g.slice_of(farthest) + 1) : uint16_t(0);
      }
  });
  dilate_3x3(g, needed, jobs, view.active_slices);
  dilate_3x3(g, view.active_slices, jobs, view.lit_slices);
}

}  // namespace cr

// Depth-aware froxel culling: per column, the slices any pixel can read.
// One parallel pass over rows of tiles reads the distance buffer once, in
// memory order (the max over each tile's pixel rows per pixel column, then
// over each tile's pixel columns); the two 3x3 dilations of the small
// per-column counts are separable (rows, then columns) and run on the caller.
#include <algorithm>

#include <xmmintrin.h>

#include "fog/froxel_passes.h"

namespace cr {

namespace {

// out[c] = max of in over the 3x3 columns around c (clamped at the edges):
// the max over 3 columns in each row, then over 3 rows.
void dilate_3x3(int nx, int ny, const std::vector<uint16_t>& in, std::vector<uint16_t>& row_max,
                std::vector<uint16_t>& out) {
  row_max.resize(in.size());
  out.resize(in.size());
  for (int y = 0; y < ny; ++y) {
    const uint16_t* a = in.data() + size_t(y) * nx;
    uint16_t* m = row_max.data() + size_t(y) * nx;
    if (nx == 1) {
      m[0] = a[0];
      continue;
    }
    m[0] = std::max(a[0], a[1]);
    for (int x = 1; x < nx - 1; ++x) m[x] = std::max(std::max(a[x - 1], a[x]), a[x + 1]);
    m[nx - 1] = std::max(a[nx - 2], a[nx - 1]);
  }
  for (int y = 0; y < ny; ++y) {
    const uint16_t* above = row_max.data() + size_t(std::max(y - 1, 0)) * nx;
    const uint16_t* row = row_max.data() + size_t(y) * nx;
    const uint16_t* below = row_max.data() + size_t(std::min(y + 1, ny - 1)) * nx;
    uint16_t* o = out.data() + size_t(y) * nx;
    for (int x = 0; x < nx; ++x) o[x] = std::max(std::max(above[x], row[x]), below[x]);
  }
}

}  // namespace

void cull_froxels_by_depth(FroxelView& view, const std::vector<float>& distance, JobSystem& jobs) {
  const FroxelGrid& g = view.grid;
  const int w = g.width(), h = g.height(), s = g.froxel_size(), nx = g.nx();
  if (distance.size() != size_t(w) * size_t(h)) return;  // no depth: keep every slice
  // NaN distances are never composited: every max below skips them ("v > m ?
  // v : m" from m = 0, and max_ps(v, m) is the same). A max is exact in any
  // order; the only pair an order could pick differently, +0 and -0, fails
  // "> near" alike.
  std::vector<uint16_t> needed(g.columns());
  jobs.parallel_for("fog.cull.tiles", size_t(g.ny()), 4, [&](size_t begin, size_t end) {
    std::vector<float> column_max(static_cast<size_t>(w));
    for (int ty = int(begin); ty < int(end); ++ty) {
      std::fill(column_max.begin(), column_max.end(), 0.0f);
      for (int y = ty * s; y < std::min((ty + 1) * s, h); ++y) {
        const float* row = distance.data() + size_t(y) * w;
        float* m = column_max.data();
        for (int x = 0; x < w; ++x) m[x] = row[x] > m[x] ? row[x] : m[x];
      }
      for (int tx = 0; tx < nx; ++tx) {
        const float* m = column_max.data();
        const int xa = tx * s, xb = std::min((tx + 1) * s, w);
        __m128 lanes = _mm_setzero_ps();
        float farthest = 0.0f;
        int x = xa;
        for (; x + 4 <= xb; x += 4) lanes = _mm_max_ps(_mm_loadu_ps(m + x), lanes);
        for (; x < xb; ++x) farthest = m[x] > farthest ? m[x] : farthest;
        alignas(16) float lane[4];
        _mm_store_ps(lane, lanes);
        for (float v : lane) farthest = v > farthest ? v : farthest;
        needed[size_t(ty) * nx + tx] =
            farthest > g.near_distance() ? uint16_t(g.slice_of(farthest) + 1) : uint16_t(0);
      }
    }
  });
  std::vector<uint16_t> row_max;
  dilate_3x3(nx, g.ny(), needed, row_max, view.active_slices);
  dilate_3x3(nx, g.ny(), view.active_slices, row_max, view.lit_slices);
}

}  // namespace cr

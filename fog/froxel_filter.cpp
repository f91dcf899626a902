// fog.filter: HDRP's 3x3 Gaussian (sigma = 1 froxel) within each slice. The
// kernel exp(-(dx^2 + dy^2) / 2) is separable, so it runs as a horizontal then
// a vertical 3-tap pass; edge taps are clamped to the grid like HDRP's
// clamped loads. With column-major storage each tap is a whole column, so the
// inner loop runs over contiguous slices.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"

namespace cr {

namespace {

void filter_axis(const FroxelGrid& g, const std::vector<glm::vec3>& in, bool horizontal, JobSystem& jobs,
                 std::vector<glm::vec3>& out) {
  const float side = std::exp(-0.5f);
  const float norm = 1.0f / (1.0f + 2.0f * side);
  const int nx = g.nx(), ny = g.ny(), nz = g.nz();
  jobs.parallel_for(horizontal ? "fog.filter.x" : "fog.filter.y", size_t(ny), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        const int xa = horizontal ? std::max(x - 1, 0) : x, xb = horizontal ? std::min(x + 1, nx - 1) : x;
        const int ya = horizontal ? y : std::max(y - 1, 0), yb = horizontal ? y : std::min(y + 1, ny - 1);
        const glm::vec3* a = in.data() + g.index(xa, ya, 0);
        const glm::vec3* c = in.data() + g.index(x, y, 0);
        const glm::vec3* b = in.data() + g.index(xb, yb, 0);
        glm::vec3* o = out.data() + g.index(x, y, 0);
        for (int k = 0; k < nz; ++k) o[k] = (c[k] + (a[k] + b[k]) * side) * norm;
      }
  });
}

}  // namespace

void filter_slices(const FroxelGrid& grid, const std::vector<glm::vec3>& in, JobSystem& jobs,
                   std::vector<glm::vec3>& scratch, std::vector<glm::vec3>& out) {
  scratch.resize(grid.count());
  out.resize(grid.count());
  filter_axis(grid, in, true, jobs, scratch);
  filter_axis(grid, scratch, false, jobs, out);
}

}  // namespace cr

// Per-pixel application of the integrated froxel volume. Across columns the
// lookup is bilinear (froxel centres); along depth it is exact for the
// froxel's homogeneous medium: at distance s into a slice of length dt,
//   L = L_near + (L_far - L_near) (1 - exp(-sigma s)) / (1 - exp(-sigma dt)),
//   T = T_near exp(-sigma s),
// so the lookup never adds light from behind the pixel's surface.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"

namespace cr {

void lookup_fog(const FroxelGrid& g, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  in_scatter = glm::vec3(0.0f);
  transmittance = 1.0f;
  if (!(distance > g.near_distance())) return;
  const float d = std::min(distance, g.far_distance());
  const int nz = g.nz();
  const int k = std::clamp(int(g.slice_coord(d)), 0, nz - 1);
  const float s = std::max(d - g.boundary(k), 0.0f);
  const float dt = g.thickness(k);
  const float size = float(g.froxel_size());
  const float fx = std::clamp(px / size - 0.5f, 0.0f, float(g.nx() - 1));
  const float fy = std::clamp(py / size - 0.5f, 0.0f, float(g.ny() - 1));
  const int x0 = int(fx), y0 = int(fy);
  const int x1 = std::min(x0 + 1, g.nx() - 1), y1 = std::min(y0 + 1, g.ny() - 1);
  const float ax = fx - float(x0), ay = fy - float(y0);
  const int xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
  const float ws[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
  glm::vec3 l_near(0.0f), l_far(0.0f);
  float t_near = 0.0f, sigma = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const size_t at = g.index(xs[i], ys[i], k);
    const IntegratedFroxel& far = volume[at];
    l_far += far.in_scatter * ws[i];
    sigma += far.extinction * ws[i];
    if (k > 0) {
      l_near += volume[at - 1].in_scatter * ws[i];
      t_near += volume[at - 1].transmittance * ws[i];
    } else {
      t_near += ws[i];
    }
  }
  const float a = sigma * s, b = sigma * dt;
  const float partial = opacity_of(a);
  const float whole = opacity_of(b);
  const float fraction = whole > 1e-12f ? partial / whole : (dt > 0.0f ? s / dt : 1.0f);
  const float slice_t = 1.0f - partial;
  in_scatter = l_near + (l_far - l_near) * fraction;
  transmittance = t_near * slice_t;
}

void composite_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      glm::vec3 in_scatter;
      float transmittance;
      lookup_fog(grid, volume, float(x) + 0.5f, float(y) + 0.5f, distance[i], in_scatter, transmittance);
      color[i] = color[i] * transmittance + in_scatter;
    }
}

}  // namespace cr

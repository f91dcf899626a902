// Per-pixel application of the integrated froxel volume. Across columns the
// lookup is bilinear (froxel centres); along depth it is exact for the
// froxel's homogeneous medium: at distance s into a slice of length dt,
//   L = L_near + (L_far - L_near) (1 - exp(-sigma s)) / (1 - exp(-sigma dt)),
//   T = T_near exp(-sigma s),
// so the lookup never adds light from behind the pixel's surface. Pixels at
// or beyond the far end (sky) take the columns' integrated end values: no
// slice search, no exp. The slice comes from FroxelGrid::slice_of (a table
// and boundary compares, no log), and the composite sets up each row's and
// column's bilinear terms once.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"

namespace cr {

namespace {

// Bilinear footprint along one axis at pixel coordinate p.
struct Axis {
  int i0, i1;
  float a;
};

Axis axis_at(float p, float inv_size, int n) {
  const float f = std::clamp(p * inv_size - 0.5f, 0.0f, float(n - 1));
  Axis ax;
  ax.i0 = int(f);
  ax.i1 = std::min(ax.i0 + 1, n - 1);
  ax.a = f - float(ax.i0);
  return ax;
}

void lookup(const FroxelGrid& g, const IntegratedFroxel* volume, const Axis& ax, const Axis& ay, float distance,
            glm::vec3& in_scatter, float& transmittance) {
  const int nz = g.nz(), nx = g.nx();
  const size_t at[4] = {(size_t(ay.i0) * nx + ax.i0) * nz, (size_t(ay.i0) * nx + ax.i1) * nz,
                        (size_t(ay.i1) * nx + ax.i0) * nz, (size_t(ay.i1) * nx + ax.i1) * nz};
  const float ws[4] = {(1 - ax.a) * (1 - ay.a), ax.a * (1 - ay.a), (1 - ax.a) * ay.a, ax.a * ay.a};
  if (distance >= g.far_distance()) {
    glm::vec3 l(0.0f);
    float t = 0.0f;
    for (int i = 0; i < 4; ++i) {
      const IntegratedFroxel& f = volume[at[i] + size_t(nz - 1)];
      l += f.in_scatter * ws[i];
      t += f.transmittance * ws[i];
    }
    in_scatter = l;
    transmittance = t;
    return;
  }
  const int k = g.slice_of(distance);
  const float s = std::max(distance - g.boundary(k), 0.0f);
  const float dt = g.thickness(k);
  glm::vec3 l_near(0.0f), l_far(0.0f);
  float t_near = 0.0f, sigma = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const IntegratedFroxel* c = volume + at[i] + size_t(k);
    l_far += c->in_scatter * ws[i];
    sigma += c->extinction * ws[i];
    if (k > 0) {
      l_near += c[-1].in_scatter * ws[i];
      t_near += c[-1].transmittance * ws[i];
    } else {
      t_near += ws[i];
    }
  }
  const float a = sigma * s, b = sigma * dt;
  const float partial = opacity_of(a);
  const float whole = opacity_of(b);
  const float fraction = whole > 1e-12f ? partial / whole : (dt > 0.0f ? s / dt : 1.0f);
  in_scatter = l_near + (l_far - l_near) * fraction;
  transmittance = t_near * (1.0f - partial);
}

}  // namespace

void lookup_fog(const FroxelGrid& g, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  in_scatter = glm::vec3(0.0f);
  transmittance = 1.0f;
  if (!(distance > g.near_distance())) return;
  const float inv_size = 1.0f / float(g.froxel_size());
  lookup(g, volume.data(), axis_at(px, inv_size, g.nx()), axis_at(py, inv_size, g.ny()), distance, in_scatter,
         transmittance);
}

void composite_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1) {
  if (x1 <= x0 || y1 <= y0) return;
  const float inv_size = 1.0f / float(grid.froxel_size());
  const float near = grid.near_distance();
  std::vector<Axis> columns(size_t(x1 - x0));
  for (int x = x0; x < x1; ++x) columns[size_t(x - x0)] = axis_at(float(x) + 0.5f, inv_size, grid.nx());
  for (int y = y0; y < y1; ++y) {
    const Axis ay = axis_at(float(y) + 0.5f, inv_size, grid.ny());
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const float d = distance[i];
      if (!(d > near)) continue;  // in front of the grid (or no distance): no fog
      glm::vec3 in_scatter;
      float transmittance;
      lookup(grid, volume.data(), columns[size_t(x - x0)], ay, d, in_scatter, transmittance);
      color[i] = color[i] * transmittance + in_scatter;
    }
  }
}

}  // namespace cr

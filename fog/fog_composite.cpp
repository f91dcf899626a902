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
//
// The composite runs a row of pixels in two steps: the bilinear reads of the
// slice's near and far values per pixel (scalar: the slice varies per pixel),
// then the two exponentials and the blend for the whole row as flat loops
// over SoA arrays, which vectorise (the exponential's polynomial is a long
// dependency chain, so one pixel at a time leaves the core idle).
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

// Pixels inside the grid, between the bilinear reads and the in-slice
// closed form: near/far in-scattered radiance, near transmittance, the
// slice's extinction, the distance into the slice and its length. The
// closed form overwrites l_far with the pixel's in-scatter and t_near with
// its transmittance.
struct SliceBatch {
  std::vector<float> near_r, near_g, near_b, far_r, far_g, far_b, t_near, sigma, s, dt;
  explicit SliceBatch(size_t n)
      : near_r(n), near_g(n), near_b(n), far_r(n), far_g(n), far_b(n), t_near(n), sigma(n), s(n), dt(n) {}
};

struct Weights {
  size_t at[4];
  float w[4];
};

Weights weights_of(const FroxelGrid& g, const Axis& ax, const Axis& ay) {
  const int nz = g.nz(), nx = g.nx();
  return Weights{{(size_t(ay.i0) * nx + ax.i0) * nz, (size_t(ay.i0) * nx + ax.i1) * nz,
                  (size_t(ay.i1) * nx + ax.i0) * nz, (size_t(ay.i1) * nx + ax.i1) * nz},
                 {(1 - ax.a) * (1 - ay.a), ax.a * (1 - ay.a), (1 - ax.a) * ay.a, ax.a * ay.a}};
}

// Sky (at or beyond the far end): the columns' integrated end values.
void lookup_far(const FroxelGrid& g, const IntegratedFroxel* volume, const Weights& wt, glm::vec3& in_scatter,
                float& transmittance) {
  const int nz = g.nz();
  glm::vec3 l(0.0f);
  float t = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const IntegratedFroxel& f = volume[wt.at[i] + size_t(nz - 1)];
    l += f.in_scatter * wt.w[i];
    t += f.transmittance * wt.w[i];
  }
  in_scatter = l;
  transmittance = t;
}

// The bilinear reads of a pixel inside the grid into slot j of the batch.
void gather_slice(const FroxelGrid& g, const IntegratedFroxel* volume, const Weights& wt, float distance,
                  SliceBatch& b, size_t j) {
  const int k = g.slice_of(distance);
  glm::vec3 l_near(0.0f), l_far(0.0f);
  float t_near = 0.0f, sigma = 0.0f;
  for (int i = 0; i < 4; ++i) {
    const IntegratedFroxel* c = volume + wt.at[i] + size_t(k);
    l_far += c->in_scatter * wt.w[i];
    sigma += c->extinction * wt.w[i];
    if (k > 0) {
      l_near += c[-1].in_scatter * wt.w[i];
      t_near += c[-1].transmittance * wt.w[i];
    } else {
      t_near += wt.w[i];
    }
  }
  b.near_r[j] = l_near.x, b.near_g[j] = l_near.y, b.near_b[j] = l_near.z;
  b.far_r[j] = l_far.x, b.far_g[j] = l_far.y, b.far_b[j] = l_far.z;
  b.t_near[j] = t_near;
  b.sigma[j] = sigma;
  b.s[j] = std::max(distance - g.boundary(k), 0.0f);
  b.dt[j] = g.thickness(k);
}

// The in-slice closed form for slots [0, n) (branch-free: both divisions run
// on divisors kept off zero, then the same selects as the scalar form
// "whole > 1e-12 ? partial / whole : (dt > 0 ? s / dt : 1)"). Restrict
// parameters, so the compiler knows the arrays apart and vectorises.
void resolve_slices(
    size_t n, const float* __restrict sigma, const float* __restrict s, const float* __restrict dt,
    const float* __restrict near_r, const float* __restrict near_g, const float* __restrict near_b,
    float* __restrict far_r, float* __restrict far_g, float* __restrict far_b, float* __restrict t_near) {
  for (size_t j = 0; j < n; ++j) {
    const float partial = opacity_of(sigma[j] * s[j]);
    const float whole = opacity_of(sigma[j] * dt[j]);
    const bool has_medium = whole > 1e-12f, has_length = dt[j] > 0.0f;
    const float by_opacity = partial / (has_medium ? whole : 1.0f);
    const float by_length = s[j] / (has_length ? dt[j] : 1.0f);
    const float fraction = has_medium ? by_opacity : (has_length ? by_length : 1.0f);
    far_r[j] = near_r[j] + (far_r[j] - near_r[j]) * fraction;
    far_g[j] = near_g[j] + (far_g[j] - near_g[j]) * fraction;
    far_b[j] = near_b[j] + (far_b[j] - near_b[j]) * fraction;
    t_near[j] = t_near[j] * (1.0f - partial);
  }
}

void resolve_slices(SliceBatch& b, size_t n) {
  resolve_slices(n, b.sigma.data(), b.s.data(), b.dt.data(), b.near_r.data(), b.near_g.data(), b.near_b.data(),
                 b.far_r.data(), b.far_g.data(), b.far_b.data(), b.t_near.data());
}

}  // namespace

void lookup_fog(const FroxelGrid& g, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  in_scatter = glm::vec3(0.0f);
  transmittance = 1.0f;
  if (!(distance > g.near_distance())) return;
  const float inv_size = 1.0f / float(g.froxel_size());
  const Weights wt = weights_of(g, axis_at(px, inv_size, g.nx()), axis_at(py, inv_size, g.ny()));
  if (distance >= g.far_distance()) {
    lookup_far(g, volume.data(), wt, in_scatter, transmittance);
    return;
  }
  SliceBatch b(1);
  gather_slice(g, volume.data(), wt, distance, b, 0);
  resolve_slices(b, 1);
  in_scatter = glm::vec3(b.far_r[0], b.far_g[0], b.far_b[0]);
  transmittance = b.t_near[0];
}

void composite_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1) {
  if (x1 <= x0 || y1 <= y0) return;
  const float inv_size = 1.0f / float(grid.froxel_size());
  const float near = grid.near_distance(), far = grid.far_distance();
  std::vector<Axis> columns(size_t(x1 - x0));
  for (int x = x0; x < x1; ++x) columns[size_t(x - x0)] = axis_at(float(x) + 0.5f, inv_size, grid.nx());
  SliceBatch batch(size_t(x1 - x0));
  std::vector<size_t> pixel(size_t(x1 - x0));  // batch slot -> pixel index
  for (int y = y0; y < y1; ++y) {
    const Axis ay = axis_at(float(y) + 0.5f, inv_size, grid.ny());
    size_t n = 0;
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const float d = distance[i];
      if (!(d > near)) continue;  // in front of the grid (or no distance): no fog
      const Weights wt = weights_of(grid, columns[size_t(x - x0)], ay);
      if (d >= far) {
        glm::vec3 in_scatter;
        float transmittance;
        lookup_far(grid, volume.data(), wt, in_scatter, transmittance);
        color[i] = color[i] * transmittance + in_scatter;
        continue;
      }
      gather_slice(grid, volume.data(), wt, d, batch, n);
      pixel[n++] = i;
    }
    resolve_slices(batch, n);
    for (size_t j = 0; j < n; ++j) {
      glm::vec3& c = color[pixel[j]];
      c = c * batch.t_near[j] + glm::vec3(batch.far_r[j], batch.far_g[j], batch.far_b[j]);
    }
  }
}

}  // namespace cr

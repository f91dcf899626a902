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
// The composite runs a row of pixels in three steps: the bilinear reads of
// the slice's near and far values per pixel (the slice varies per pixel; each
// tap is one 4-wide load of radiance and transmittance), the two
// exponentials for the whole row as a flat loop that vectorises (the
// exponential's polynomial is a long dependency chain, so one pixel at a time
// leaves the core idle), then the blend per pixel, 4 wide.
#include <algorithm>
#include <cmath>

#include <cstddef>

#include <smmintrin.h>

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
// closed form: per pixel the near boundary's (radiance RGB, transmittance)
// and the far boundary's radiance as 4-float records (a froxel's first four
// floats, so each bilinear tap is one 4-wide load and multiply-add), and as
// flat arrays the slice's extinction, the distance into the slice and its
// length. The closed form's fraction and partial opacity go to `fraction`
// and `partial`.
struct SliceBatch {
  std::vector<float> near, far;  // 4 floats per slot
  std::vector<float> sigma, s, dt, fraction, partial;
  explicit SliceBatch(size_t n) : near(4 * n), far(4 * n), sigma(n), s(n), dt(n), fraction(n), partial(n) {}
};
static_assert(offsetof(IntegratedFroxel, in_scatter) == 0 && offsetof(IntegratedFroxel, transmittance) == 12,
              "a froxel's radiance and transmittance are its first four floats");

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

// Sky (at or beyond the far end): the columns' integrated end values,
// radiance in lanes 0-2 and transmittance in lane 3.
__m128 lookup_far(const FroxelGrid& g, const IntegratedFroxel* volume, const Weights& wt) {
  const size_t last = size_t(g.nz() - 1);
  __m128 sum = _mm_setzero_ps();
  for (int i = 0; i < 4; ++i)
    sum = _mm_add_ps(sum, _mm_mul_ps(_mm_loadu_ps(&volume[wt.at[i] + last].in_scatter.x), _mm_set1_ps(wt.w[i])));
  return sum;
}

// The bilinear reads of a pixel inside the grid into slot j of the batch.
// Lane-wise the same float operations, in the same order, as a sum over the
// four taps per channel. In the first slice the near boundary is the near
// plane: no radiance, transmittance 1.
void gather_slice(const FroxelGrid& g, const IntegratedFroxel* volume, const Weights& wt, float distance,
                  SliceBatch& b, size_t j) {
  const int k = g.slice_of(distance);
  __m128 near = _mm_setzero_ps(), far = _mm_setzero_ps();
  float sigma = 0.0f;
  const __m128 near_plane = _mm_set_ps(1.0f, 0.0f, 0.0f, 0.0f);
  for (int i = 0; i < 4; ++i) {
    const IntegratedFroxel* c = volume + wt.at[i] + size_t(k);
    const __m128 w = _mm_set1_ps(wt.w[i]);
    far = _mm_add_ps(far, _mm_mul_ps(_mm_loadu_ps(&c->in_scatter.x), w));
    sigma += c->extinction * wt.w[i];
    near = _mm_add_ps(near, _mm_mul_ps(k > 0 ? _mm_loadu_ps(&c[-1].in_scatter.x) : near_plane, w));
  }
  _mm_storeu_ps(&b.near[4 * j], near);
  _mm_storeu_ps(&b.far[4 * j], far);
  b.sigma[j] = sigma;
  b.s[j] = std::max(distance - g.boundary(k), 0.0f);
  b.dt[j] = g.thickness(k);
}

// The in-slice closed form's terms for slots [0, n) (branch-free: both
// divisions run on divisors kept off zero, then the same selects as the
// scalar form "whole > 1e-12 ? partial / whole : (dt > 0 ? s / dt : 1)").
// Restrict parameters, so the compiler knows the arrays apart and vectorises.
void slice_fractions(size_t n, const float* __restrict sigma, const float* __restrict s,
                     const float* __restrict dt, float* __restrict fraction, float* __restrict partial) {
  for (size_t j = 0; j < n; ++j) {
    const float p = opacity_of(sigma[j] * s[j]);
    const float whole = opacity_of(sigma[j] * dt[j]);
    const bool has_medium = whole > 1e-12f, has_length = dt[j] > 0.0f;
    const float by_opacity = p / (has_medium ? whole : 1.0f);
    const float by_length = s[j] / (has_length ? dt[j] : 1.0f);
    fraction[j] = has_medium ? by_opacity : (has_length ? by_length : 1.0f);
    partial[j] = p;
  }
}

// Slot j's in-scattered radiance (lanes 0-2) and transmittance (lane 3):
// near + (far - near) * fraction and T_near (1 - partial).
inline __m128 resolve_slot(const SliceBatch& b, size_t j) {
  const __m128 near = _mm_loadu_ps(&b.near[4 * j]);
  const __m128 far = _mm_loadu_ps(&b.far[4 * j]);
  const __m128 l = _mm_add_ps(near, _mm_mul_ps(_mm_sub_ps(far, near), _mm_set1_ps(b.fraction[j])));
  const __m128 t = _mm_mul_ps(near, _mm_set1_ps(1.0f - b.partial[j]));
  return _mm_blend_ps(l, t, 0x8);
}

void resolve_slices(SliceBatch& b, size_t n) {
  slice_fractions(n, b.sigma.data(), b.s.data(), b.dt.data(), b.fraction.data(), b.partial.data());
}

}  // namespace

void lookup_fog(const FroxelGrid& g, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  in_scatter = glm::vec3(0.0f);
  transmittance = 1.0f;
  if (!(distance > g.near_distance())) return;
  const float inv_size = 1.0f / float(g.froxel_size());
  const Weights wt = weights_of(g, axis_at(px, inv_size, g.nx()), axis_at(py, inv_size, g.ny()));
  alignas(16) float v[4];
  if (distance >= g.far_distance()) {
    _mm_store_ps(v, lookup_far(g, volume.data(), wt));
  } else {
    SliceBatch b(1);
    gather_slice(g, volume.data(), wt, distance, b, 0);
    resolve_slices(b, 1);
    _mm_store_ps(v, resolve_slot(b, 0));
  }
  in_scatter = glm::vec3(v[0], v[1], v[2]);
  transmittance = v[3];
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
        alignas(16) float v[4];
        _mm_store_ps(v, lookup_far(grid, volume.data(), wt));
        color[i] = color[i] * v[3] + glm::vec3(v[0], v[1], v[2]);
        continue;
      }
      gather_slice(grid, volume.data(), wt, d, batch, n);
      pixel[n++] = i;
    }
    resolve_slices(batch, n);
    for (size_t j = 0; j < n; ++j) {
      alignas(16) float v[4];
      _mm_store_ps(v, resolve_slot(batch, j));
      glm::vec3& c = color[pixel[j]];
      c = c * v[3] + glm::vec3(v[0], v[1], v[2]);
    }
  }
}

}  // namespace cr

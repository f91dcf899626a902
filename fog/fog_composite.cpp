// Per-pixel application of the integrated froxel volume. Across columns the
// lookup is bilinear (froxel centres); along depth it is exact for the
// froxel's homogeneous medium: at distance s into a slice of length dt,
//   L = L_near + (L_far - L_near) (1 - exp(-sigma s)) / (1 - exp(-sigma dt)),
//   T = T_near exp(-sigma s),
// so the lookup never adds light from behind the pixel's surface. Pixels at
// or beyond the far end (sky) take the columns' integrated end values: no
// slice search, no exp.
//
// lookup_fog is the definition, one pixel at a time (4-wide over radiance and
// transmittance). composite_fog computes the same float operations in the
// same order, 8 pixels at a time: a froxel spans 8 pixels, so along a row
// runs of up to 8 pixels share their 2x2 columns and differ only in weights
// and distance. Per run, the slices its pixels reach are visited in
// increasing order (the nearest pixel not yet reached picks the next one, so
// only slices some pixel lies in are read); each visit broadcasts the four
// taps' records and selects them into the lanes at or beyond the slice's
// near boundary, so sky, geometry and no-fog pixels mix in a run without
// per-pixel branches or gathers. The closed form's exponentials then run over
// the row as a flat loop, and the blend writes the colour in place, in order.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <limits>

#include <immintrin.h>

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

// ---- composite_fog: runs of 8 pixels that share their 2x2 columns ----

constexpr int kLanes = 8;
constexpr int kBand = 64;         // pixels per row segment, so a segment's per-pixel terms stay in L1
constexpr int kPrefetchRows = 2;  // rows of distance and colour requested ahead
constexpr float kNearPlane[4] = {0.0f, 0.0f, 0.0f, 1.0f};  // radiance RGB, transmittance

// Radiance RGB and transmittance, a lane per pixel.
struct Rgbt {
  __m256 c[4];
};

// The four taps of a run: each tap's column and its weight per lane.
struct RunTaps {
  const IntegratedFroxel* column[4];
  __m256 w[4];

  // The bilinear sum of slice k's radiance and transmittance (k = -1: the
  // near plane). Per channel the same float operations, in the same order,
  // as lookup_far's and gather_slice's sums over the taps.
  Rgbt at(int k) const {
    Rgbt s;
    for (__m256& c : s.c) c = _mm256_setzero_ps();
    for (int i = 0; i < 4; ++i) {
      const float* r = k < 0 ? kNearPlane : &column[i][k].in_scatter.x;
      for (int ch = 0; ch < 4; ++ch) s.c[ch] = _mm256_add_ps(s.c[ch], _mm256_mul_ps(_mm256_broadcast_ss(r + ch), w[i]));
    }
    return s;
  }
  __m256 extinction(int k) const {
    __m256 sigma = _mm256_setzero_ps();
    for (int i = 0; i < 4; ++i)
      sigma = _mm256_add_ps(sigma, _mm256_mul_ps(_mm256_broadcast_ss(&column[i][k].extinction), w[i]));
    return sigma;
  }
};

// Smallest distance among the lanes of `mask` (at least one, none NaN).
float nearest(__m256 d, __m256 mask) {
  __m256 m = _mm256_blendv_ps(_mm256_set1_ps(std::numeric_limits<float>::infinity()), d, mask);
  m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
  m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
  m = _mm256_min_ps(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm256_cvtss_f32(m);
}

// One segment of a row, per pixel (structure of arrays, kLanes of padding so
// a run's full-width store stays inside): the slice's near and far values
// (sky: the far end's values in `far`), extinction, distance into the slice
// and its length, the closed form's terms, and which pixels are fogged or sky.
struct RowBatch {
  std::vector<float> store;
  float *near[4], *far[4], *sigma, *s, *dt, *fraction, *partial;
  std::vector<int32_t> fog, sky;  // all bits set where true
  explicit RowBatch(size_t n) : store(15 * n), fog(n), sky(n) {
    float* p = store.data();
    for (float*& a : near) a = p, p += n;
    for (float*& a : far) a = p, p += n;
    for (float** a : {&sigma, &s, &dt, &fraction, &partial}) *a = p, p += n;
  }
};

template <class T>
void store_lanes(T* at, __m256 v) {
  _mm256_storeu_ps(reinterpret_cast<float*>(at), v);
}

// The pixels of a run (the `valid` lanes) at slot j: distance d per lane
// (other lanes are ignored and their slots overwritten by the next run).
void gather_run(const FroxelGrid& g, const RunTaps& taps, __m256 d, __m256 valid, RowBatch& b, size_t j) {
  // In front of the grid (or no distance): no fog. At or beyond the far end: sky.
  const __m256 fog = _mm256_and_ps(valid, _mm256_cmp_ps(d, _mm256_set1_ps(g.near_distance()), _CMP_GT_OQ));
  const __m256 sky = _mm256_and_ps(fog, _mm256_cmp_ps(d, _mm256_set1_ps(g.far_distance()), _CMP_GE_OQ));
  const __m256 inside = _mm256_andnot_ps(sky, fog);
  Rgbt near{}, far{};
  __m256 sigma = _mm256_setzero_ps(), start = _mm256_setzero_ps(), dt = _mm256_setzero_ps();
  if (_mm256_movemask_ps(inside)) {
    // Each visit's slice holds the nearest inside lane not yet reached; lanes
    // at or beyond its near boundary take it, so each lane ends with its own
    // slice (slice_of is exact against the boundaries, which increase).
    int k = g.slice_of(nearest(d, inside));
    int held = INT_MIN;  // the slice whose sum `at_k` holds
    Rgbt at_k{};
    for (;;) {
      const Rgbt before = held == k - 1 ? at_k : taps.at(k - 1);
      at_k = taps.at(k);
      held = k;
      const __m256 reached = _mm256_cmp_ps(d, _mm256_set1_ps(g.boundary(k)), _CMP_GE_OQ);
      for (int ch = 0; ch < 4; ++ch) {
        near.c[ch] = _mm256_blendv_ps(near.c[ch], before.c[ch], reached);
        far.c[ch] = _mm256_blendv_ps(far.c[ch], at_k.c[ch], reached);
      }
      sigma = _mm256_blendv_ps(sigma, taps.extinction(k), reached);
      start = _mm256_blendv_ps(start, _mm256_set1_ps(g.boundary(k)), reached);
      dt = _mm256_blendv_ps(dt, _mm256_set1_ps(g.thickness(k)), reached);
      if (k + 1 == g.nz()) break;
      const __m256 beyond = _mm256_and_ps(inside, _mm256_cmp_ps(d, _mm256_set1_ps(g.boundary(k + 1)), _CMP_GE_OQ));
      if (!_mm256_movemask_ps(beyond)) break;
      k = g.slice_of(nearest(d, beyond));
    }
  }
  if (_mm256_movemask_ps(sky)) {
    const Rgbt end = taps.at(g.nz() - 1);
    for (int ch = 0; ch < 4; ++ch) far.c[ch] = _mm256_blendv_ps(far.c[ch], end.c[ch], sky);
  }
  for (int ch = 0; ch < 4; ++ch) {
    store_lanes(b.near[ch] + j, near.c[ch]);
    store_lanes(b.far[ch] + j, far.c[ch]);
  }
  store_lanes(b.sigma + j, sigma);
  // max(0, x) is std::max(x, 0.0f), NaN and signed zeros included.
  store_lanes(b.s + j, _mm256_max_ps(_mm256_setzero_ps(), _mm256_sub_ps(d, start)));
  store_lanes(b.dt + j, dt);
  store_lanes(b.fog.data() + j, fog);
  store_lanes(b.sky.data() + j, sky);
}

// colour = colour * T + L for slots [0, n) of a row segment: resolve_slot's
// float operations, or the far end's values for sky. Restrict pointers, so
// the compiler knows the arrays apart and vectorises.
void blend_row(const RowBatch& b, size_t n, glm::vec3* color) {
  float* __restrict c = &color->x;
  const float* __restrict near[4] = {b.near[0], b.near[1], b.near[2], b.near[3]};
  const float* __restrict far[4] = {b.far[0], b.far[1], b.far[2], b.far[3]};
  const float* __restrict fraction = b.fraction;
  const float* __restrict partial = b.partial;
  const int32_t* __restrict fog = b.fog.data();
  const int32_t* __restrict sky = b.sky.data();
  for (size_t j = 0; j < n; ++j) {
    const float t = sky[j] ? far[3][j] : near[3][j] * (1.0f - partial[j]);
    for (int ch = 0; ch < 3; ++ch) {
      const float l = sky[j] ? far[ch][j] : near[ch][j] + (far[ch][j] - near[ch][j]) * fraction[j];
      c[3 * j + ch] = fog[j] ? c[3 * j + ch] * t + l : c[3 * j + ch];
    }
  }
}

// Requests [begin, begin + bytes) into the cache ahead of use: a band's rows
// lie a frame width apart, a stride the hardware prefetchers do not follow
// in time.
void prefetch(const void* begin, size_t bytes) {
  const char* p = static_cast<const char*>(begin);
  for (size_t o = 0; o < bytes; o += 64) _mm_prefetch(p + o, _MM_HINT_T0);
  _mm_prefetch(p + bytes - 1, _MM_HINT_T0);
}

// Pixels [x0, x1) x [y0, y1) with x1 - x0 <= kBand.
void composite_band(const FroxelGrid& grid, const IntegratedFroxel* volume, const float* distance,
                    glm::vec3* color, int width, int x0, int y0, int x1, int y1, RowBatch& b) {
  const float inv_size = 1.0f / float(grid.froxel_size());
  const size_t n = size_t(x1 - x0);
  // Runs: consecutive pixels with the same columns, at most kLanes each.
  struct Run {
    int x, len;
    Axis ax;
  };
  Run runs[kBand];
  int run_count = 0;
  alignas(32) float column_weight[kBand + kLanes] = {};  // each pixel's ax.a
  for (int x = x0; x < x1; ++x) {
    const Axis ax = axis_at(float(x) + 0.5f, inv_size, grid.nx());
    column_weight[x - x0] = ax.a;
    Run* last = run_count ? &runs[run_count - 1] : nullptr;
    if (last && last->ax.i0 == ax.i0 && last->len < kLanes)
      ++last->len;
    else
      runs[run_count++] = Run{x - x0, 1, ax};
  }
  const int nx = grid.nx(), nz = grid.nz();
  for (int y = y0; y < y1; ++y) {
    const Axis ay = axis_at(float(y) + 0.5f, inv_size, grid.ny());
    const __m256 ay_a = _mm256_set1_ps(ay.a), ay_1 = _mm256_set1_ps(1 - ay.a);
    const size_t row = size_t(y) * size_t(width) + size_t(x0);
    if (y + kPrefetchRows < y1) {
      const size_t ahead = row + size_t(kPrefetchRows) * size_t(width);
      prefetch(distance + ahead, n * sizeof(float));
      prefetch(color + ahead, n * sizeof(glm::vec3));
    }
    const IntegratedFroxel* row0 = volume + size_t(ay.i0) * nx * nz;
    const IntegratedFroxel* row1 = volume + size_t(ay.i1) * nx * nz;
    for (int r = 0; r < run_count; ++r) {
      const Run& run = runs[r];
      const __m256 a = _mm256_loadu_ps(column_weight + run.x), a_1 = _mm256_sub_ps(_mm256_set1_ps(1.0f), a);
      // weights_of's products, per lane.
      const RunTaps taps{{row0 + size_t(run.ax.i0) * nz, row0 + size_t(run.ax.i1) * nz,
                          row1 + size_t(run.ax.i0) * nz, row1 + size_t(run.ax.i1) * nz},
                         {_mm256_mul_ps(a_1, ay_1), _mm256_mul_ps(a, ay_1), _mm256_mul_ps(a_1, ay_a),
                          _mm256_mul_ps(a, ay_a)}};
      const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
      const __m256 valid = _mm256_cmp_ps(lane, _mm256_set1_ps(float(run.len)), _CMP_LT_OQ);
      const __m256 d = _mm256_maskload_ps(distance + row + size_t(run.x), _mm256_castps_si256(valid));
      gather_run(grid, taps, d, valid, b, size_t(run.x));
    }
    slice_fractions(n, b.sigma, b.s, b.dt, b.fraction, b.partial);
    blend_row(b, n, color + row);
  }
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
  RowBatch batch(size_t(std::min(x1 - x0, kBand) + kLanes));
  for (int bx = x0; bx < x1; bx += kBand)
    composite_band(grid, volume.data(), distance.data(), color.data(), width, bx, y0, std::min(x1, bx + kBand), y1,
                   batch);
}

}  // namespace cr

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
// and distance. A first pass over a row finds each run's fogged and sky
// pixels and the slice of its nearest pixel inside the grid (a chain of
// dependent loads, kept out of the second pass's way). The second pass
// finishes each run with fog in registers. Its pixels inside the grid visit
// the slices some pixel of the run lies in, in increasing order (the nearest
// pixel not yet reached picks the next one); each visit broadcasts the four
// taps' records and selects them into the lanes at or beyond the slice's
// near boundary, and the closed form then runs once over the 8 lanes
// through the definition's own loop. Sky pixels take the four taps' far end
// only. The run's colours are loaded as three registers, transposed to one
// register per channel, blended, transposed back and stored; runs without
// fog are not touched, runs of sky skip the slice search and the closed form.
//
// Both volumes are read through a reader giving a froxel as the float record
// (radiance RGB, transmittance) and its slice's extinction: the float
// volume's own floats, or the fixed-point volume's codes decoded
// (fixed_volume.h). Everything after the read is the same float code.
#include <algorithm>
#include <vector>
#include <cmath>
#include <cstddef>
#include <limits>

#include <immintrin.h>

#include "fog/fixed_volume.h"
#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/sun_term_format.h"

namespace cr {

namespace {

static_assert(offsetof(IntegratedFroxel, in_scatter) == 0 && offsetof(IntegratedFroxel, transmittance) == 12,
              "a froxel's radiance and transmittance are its first four floats");

// The float volume: a froxel's record is its first four floats.
struct FloatFroxels {
  const IntegratedFroxel* volume;
  const float* record(size_t i) const { return &volume[i].in_scatter.x; }
  __m128 load(size_t i) const { return _mm_loadu_ps(record(i)); }
  // Of froxel i, slice k of its column.
  float extinction(size_t i, int) const { return volume[i].extinction; }
};

// The fixed-point volume, decoded: radiance from hdr16, transmittance as
// q15 of the depth code, extinction from the depth codes of the slice's two
// boundaries (the near plane's is 0) over its thickness. A record decodes
// each channel as it is read (a run's radiance-only reads skip the
// transmittance's table lookups).
struct FixedFroxels {
  struct Record {
    const FixedIntegratedFroxel* f;
    float operator[](int ch) const {
      return ch < 3 ? fx::decode_hdr16(f->in_scatter[ch]) : Q15SunTerm::decode(transmittance_q15(f->optical_depth));
    }
  };
  const FixedIntegratedFroxel* volume;
  std::vector<float> extinction_per_code;  // per slice: the extinction of one depth code
  FixedFroxels(const FixedIntegratedFroxel* v, const FroxelGrid& grid)
      : volume(v), extinction_per_code(size_t(grid.nz())) {
    for (int k = 0; k < grid.nz(); ++k) {
      const float dt = grid.thickness(k);
      extinction_per_code[size_t(k)] = dt > 0.0f ? kOpticalDepthPerCode / dt : 0.0f;
    }
  }
  Record record(size_t i) const { return Record{volume + i}; }
  __m128 load(size_t i) const {
    const Record r = record(i);
    return _mm_setr_ps(r[0], r[1], r[2], r[3]);
  }
  float extinction(size_t i, int k) const {
    const int before = k > 0 ? volume[i - 1].optical_depth : 0;
    return float(volume[i].optical_depth - before) * extinction_per_code[size_t(k)];
  }
};

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

// A pixel inside the grid, between the bilinear reads and the in-slice
// closed form: the near boundary's (radiance RGB, transmittance) and the far
// boundary's radiance as 4-float records (a froxel's first four floats, so
// each bilinear tap is one 4-wide load and multiply-add), the slice's
// extinction, the distance into the slice and its length.
struct PixelSlice {
  __m128 near, far;
  float sigma, s, dt;
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

// Sky (at or beyond the far end): the columns' integrated end values,
// radiance in lanes 0-2 and transmittance in lane 3.
template <class Froxels>
__m128 lookup_far(const FroxelGrid& g, const Froxels& volume, const Weights& wt) {
  const size_t last = size_t(g.nz() - 1);
  __m128 sum = _mm_setzero_ps();
  for (int i = 0; i < 4; ++i)
    sum = _mm_add_ps(sum, _mm_mul_ps(volume.load(wt.at[i] + last), _mm_set1_ps(wt.w[i])));
  return sum;
}

// The bilinear reads of a pixel inside the grid. Lane-wise the same float
// operations, in the same order, as a sum over the four taps per channel. In
// the first slice the near boundary is the near plane: no radiance,
// transmittance 1.
template <class Froxels>
PixelSlice gather_slice(const FroxelGrid& g, const Froxels& volume, const Weights& wt, float distance) {
  const int k = g.slice_of(distance);
  PixelSlice p{_mm_setzero_ps(), _mm_setzero_ps(), 0.0f, std::max(distance - g.boundary(k), 0.0f), g.thickness(k)};
  const __m128 near_plane = _mm_set_ps(1.0f, 0.0f, 0.0f, 0.0f);
  for (int i = 0; i < 4; ++i) {
    const size_t c = wt.at[i] + size_t(k);
    const __m128 w = _mm_set1_ps(wt.w[i]);
    p.far = _mm_add_ps(p.far, _mm_mul_ps(volume.load(c), w));
    p.sigma += volume.extinction(c, k) * wt.w[i];
    p.near = _mm_add_ps(p.near, _mm_mul_ps(k > 0 ? volume.load(c - 1) : near_plane, w));
  }
  return p;
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

// The pixel's in-scattered radiance (lanes 0-2) and transmittance (lane 3):
// near + (far - near) * fraction and T_near (1 - partial).
__m128 resolve_pixel(const PixelSlice& p) {
  float fraction, partial;
  slice_fractions(1, &p.sigma, &p.s, &p.dt, &fraction, &partial);
  const __m128 l = _mm_add_ps(p.near, _mm_mul_ps(_mm_sub_ps(p.far, p.near), _mm_set1_ps(fraction)));
  const __m128 t = _mm_mul_ps(p.near, _mm_set1_ps(1.0f - partial));
  return _mm_blend_ps(l, t, 0x8);
}

#ifdef __AVX2__
// ---- composite_fog: runs of 8 pixels that share their 2x2 columns ----

constexpr int kLanes = 8;
constexpr int kPrefetchRows = 2;  // rows of distance and colour requested ahead
constexpr float kNearPlane[4] = {0.0f, 0.0f, 0.0f, 1.0f};  // radiance RGB, transmittance

// Radiance RGB and transmittance, a lane per pixel.
struct Rgbt {
  __m256 c[4];
};

// The four taps of a run: each tap's column (its first froxel) and its weight per lane.
template <class Froxels>
struct RunTaps {
  const Froxels& volume;
  size_t column[4];
  __m256 w[4];

  // The bilinear sum of slice k's radiance and transmittance (k = -1: the
  // near plane), its first `channels` channels (the rest 0). Per channel the
  // same float operations, in the same order, as lookup_far's and
  // gather_slice's sums over the taps.
  Rgbt at(int k, int channels = 4) const {
    Rgbt s;
    for (__m256& c : s.c) c = _mm256_setzero_ps();
    for (int i = 0; i < 4; ++i) {
      auto add = [&](const auto& r) {
        for (int ch = 0; ch < channels; ++ch)
          s.c[ch] = _mm256_add_ps(s.c[ch], _mm256_mul_ps(_mm256_set1_ps(r[ch]), w[i]));
      };
      if (k < 0)
        add(kNearPlane);
      else
        add(volume.record(column[i] + size_t(k)));
    }
    return s;
  }
  __m256 extinction(int k) const {
    __m256 sigma = _mm256_setzero_ps();
    for (int i = 0; i < 4; ++i)
      sigma = _mm256_add_ps(sigma, _mm256_mul_ps(_mm256_set1_ps(volume.extinction(column[i] + size_t(k), k)), w[i]));
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

// Radiance RGB (c[0..2]) and transmittance (c[3]) of the `inside` lanes of a
// run at distance d: resolve_pixel's float operations on gather_slice's sums.
// Each visit's slice holds the nearest inside lane not yet reached; lanes at
// or beyond its near boundary take it, so each lane ends with its own slice
// (slice_of is exact against the boundaries, which increase). The first
// visit, slice k, is the nearest inside lane's.
template <class Froxels>
Rgbt resolve_inside(const FroxelGrid& g, const RunTaps<Froxels>& taps, __m256 d, __m256 inside, int k) {
  // Slice k's radiance: a far boundary's transmittance is not used (only a
  // near boundary's, taken when a later visit starts there).
  Rgbt at_k = taps.at(k, 3);
  Rgbt near = taps.at(k - 1), far = at_k;
  __m256 sigma = taps.extinction(k), start = _mm256_set1_ps(g.boundary(k)), dt = _mm256_set1_ps(g.thickness(k));
  while (k + 1 < g.nz()) {
    const __m256 beyond = _mm256_and_ps(inside, _mm256_cmp_ps(d, _mm256_set1_ps(g.boundary(k + 1)), _CMP_GE_OQ));
    if (!_mm256_movemask_ps(beyond)) break;
    const int next = g.slice_of(nearest(d, beyond));
    Rgbt before = at_k;
    if (next == k + 1)
      before.c[3] = taps.at(k).c[3];
    else
      before = taps.at(next - 1);
    k = next;
    at_k = taps.at(k, 3);
    const __m256 reached = _mm256_cmp_ps(d, _mm256_set1_ps(g.boundary(k)), _CMP_GE_OQ);
    for (int ch = 0; ch < 4; ++ch) near.c[ch] = _mm256_blendv_ps(near.c[ch], before.c[ch], reached);
    for (int ch = 0; ch < 3; ++ch) far.c[ch] = _mm256_blendv_ps(far.c[ch], at_k.c[ch], reached);
    sigma = _mm256_blendv_ps(sigma, taps.extinction(k), reached);
    start = _mm256_blendv_ps(start, _mm256_set1_ps(g.boundary(k)), reached);
    dt = _mm256_blendv_ps(dt, _mm256_set1_ps(g.thickness(k)), reached);
  }
  // The closed form's terms through the definition's own loop (8 slots).
  alignas(32) float sigma_of[kLanes], s_of[kLanes], dt_of[kLanes], fraction_of[kLanes], partial_of[kLanes];
  _mm256_store_ps(sigma_of, sigma);
  // max(0, x) is std::max(x, 0.0f), NaN and signed zeros included.
  _mm256_store_ps(s_of, _mm256_max_ps(_mm256_setzero_ps(), _mm256_sub_ps(d, start)));
  _mm256_store_ps(dt_of, dt);
  slice_fractions(kLanes, sigma_of, s_of, dt_of, fraction_of, partial_of);
  const __m256 fraction = _mm256_load_ps(fraction_of);
  Rgbt out;
  for (int ch = 0; ch < 3; ++ch)
    out.c[ch] = _mm256_add_ps(near.c[ch], _mm256_mul_ps(_mm256_sub_ps(far.c[ch], near.c[ch]), fraction));
  out.c[3] = _mm256_mul_ps(near.c[3], _mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_load_ps(partial_of)));
  return out;
}

// 8 pixels' colours (24 floats, 3 registers) <-> a register per channel.
// A blend gathers each channel's 8 values into one register (in a fixed
// order that one permute sorts), and the inverse permute and blends put
// them back.
constexpr int kFromFirst = 0b01001001, kFromSecond = 0b10010010;  // lanes {0,3,6} and {1,4,7}
__m256 mix3(__m256 a, __m256 b, __m256 c) {  // a at {0,3,6}, b at {1,4,7}, c at {2,5}
  return _mm256_blend_ps(_mm256_blend_ps(a, b, kFromSecond), c, 0xff & ~(kFromFirst | kFromSecond));
}
// The permutes (R's and B's are their own inverses).
__m256i sort_r() { return _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5); }
__m256i sort_g() { return _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6); }
__m256i unsort_g() { return _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2); }
__m256i sort_b() { return _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7); }

void to_channels(const __m256 aos[3], __m256 rgb[3]) {
  rgb[0] = _mm256_permutevar8x32_ps(mix3(aos[0], aos[1], aos[2]), sort_r());
  rgb[1] = _mm256_permutevar8x32_ps(mix3(aos[2], aos[0], aos[1]), sort_g());
  rgb[2] = _mm256_permutevar8x32_ps(mix3(aos[1], aos[2], aos[0]), sort_b());
}

void to_pixels(const __m256 rgb[3], __m256 aos[3]) {
  const __m256 r = _mm256_permutevar8x32_ps(rgb[0], sort_r());
  const __m256 g = _mm256_permutevar8x32_ps(rgb[1], unsort_g());
  const __m256 b = _mm256_permutevar8x32_ps(rgb[2], sort_b());
  aos[0] = mix3(r, g, b);
  aos[1] = mix3(b, r, g);
  aos[2] = mix3(g, b, r);
}

// colour = colour * T + L for the `fog` lanes of a run of `len` pixels at `color`.
void blend_run(glm::vec3* color, int len, __m256 fog, const Rgbt& fogged) {
  float* c = &color->x;
  // Floats of the run: all 24, or the first 3 len (masked, so a cut run
  // touches no pixel outside it).
  const bool whole = len == kLanes;
  __m256 aos[3], rgb[3];
  __m256i part[3];
  for (int r = 0; r < 3; ++r) {
    part[r] = _mm256_cmpgt_epi32(_mm256_set1_epi32(3 * len - kLanes * r), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    aos[r] = whole ? _mm256_loadu_ps(c + kLanes * r) : _mm256_maskload_ps(c + kLanes * r, part[r]);
  }
  to_channels(aos, rgb);
  for (int ch = 0; ch < 3; ++ch)
    rgb[ch] = _mm256_blendv_ps(rgb[ch], _mm256_add_ps(_mm256_mul_ps(rgb[ch], fogged.c[3]), fogged.c[ch]), fog);
  to_pixels(rgb, aos);
  for (int r = 0; r < 3; ++r) {
    if (whole)
      _mm256_storeu_ps(c + kLanes * r, aos[r]);
    else
      _mm256_maskstore_ps(c + kLanes * r, part[r], aos[r]);
  }
}

// What the first pass over a row finds per run: which lanes are fogged and
// which sky (movemask bits), and the slice of its nearest pixel inside the
// grid. The slice search is a chain of dependent loads that the second pass
// then need not wait for.
struct RunStart {
  int fog, sky, slice;
};

// In front of the grid (or no distance): no fog. At or beyond the far end: sky.
__m256 fog_lanes(const FroxelGrid& g, __m256 d, __m256 valid) {
  return _mm256_and_ps(valid, _mm256_cmp_ps(d, _mm256_set1_ps(g.near_distance()), _CMP_GT_OQ));
}
__m256 sky_lanes(const FroxelGrid& g, __m256 d, __m256 fog) {
  return _mm256_and_ps(fog, _mm256_cmp_ps(d, _mm256_set1_ps(g.far_distance()), _CMP_GE_OQ));
}

RunStart start_of(const FroxelGrid& g, __m256 d, __m256 valid) {
  const __m256 fog = fog_lanes(g, d, valid), sky = sky_lanes(g, d, fog);
  // No inside lane: the far end's slice, unused.
  return RunStart{_mm256_movemask_ps(fog), _mm256_movemask_ps(sky), g.slice_of(nearest(d, _mm256_andnot_ps(sky, fog)))};
}

// One run with fog: `valid` lanes of distance d, colours at `color`. Sky
// lanes take the columns' far end (lookup_far's sums), lanes inside the grid
// resolve_inside's; runs of sky skip the slice search.
template <class Froxels>
void composite_run(const FroxelGrid& g, const RunTaps<Froxels>& taps, __m256 d, __m256 valid, const RunStart& start,
                   int len, glm::vec3* color) {
  const __m256 fog = fog_lanes(g, d, valid), sky = sky_lanes(g, d, fog);
  Rgbt fogged;
  if (start.fog != start.sky) fogged = resolve_inside(g, taps, d, _mm256_andnot_ps(sky, fog), start.slice);
  if (start.sky) {
    const Rgbt end = taps.at(g.nz() - 1);
    if (start.fog == start.sky)
      fogged = end;
    else
      for (int ch = 0; ch < 4; ++ch) fogged.c[ch] = _mm256_blendv_ps(fogged.c[ch], end.c[ch], sky);
  }
  blend_run(color, len, fog, fogged);
}

// Requests [begin, begin + bytes) into the cache ahead of use: a tile's rows
// lie a frame width apart, a stride the hardware prefetchers do not follow
// in time.
void prefetch(const void* begin, size_t bytes) {
  const char* p = static_cast<const char*>(begin);
  for (size_t o = 0; o < bytes; o += 64) _mm_prefetch(p + o, _MM_HINT_T0);
  _mm_prefetch(p + bytes - 1, _MM_HINT_T0);
}
#endif  // __AVX2__

template <class Froxels>
void lookup(const FroxelGrid& g, const Froxels& volume, float px, float py, float distance, glm::vec3& in_scatter,
            float& transmittance) {
  in_scatter = glm::vec3(0.0f);
  transmittance = 1.0f;
  if (!(distance > g.near_distance())) return;
  const float inv_size = 1.0f / float(g.froxel_size());
  const Weights wt = weights_of(g, axis_at(px, inv_size, g.nx()), axis_at(py, inv_size, g.ny()));
  alignas(16) float v[4];
  if (distance >= g.far_distance()) {
    _mm_store_ps(v, lookup_far(g, volume, wt));
  } else {
    _mm_store_ps(v, resolve_pixel(gather_slice(g, volume, wt, distance)));
  }
  in_scatter = glm::vec3(v[0], v[1], v[2]);
  transmittance = v[3];
}

template <class Froxels>
void composite_rows(const FroxelGrid& grid, const Froxels& volume, const std::vector<float>& distance,
                    std::vector<glm::vec3>& color, int width, int x0, int y0, int x1, int y1) {
  if (x1 <= x0 || y1 <= y0) return;
#ifndef __AVX2__
  // Builds for CPUs without AVX2 (CR_ARCH x86-64-v2): the definition, one pixel at a time.
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      if (!(distance[i] > grid.near_distance())) continue;
      glm::vec3 in_scatter;
      float transmittance;
      lookup(grid, volume, float(x) + 0.5f, float(y) + 0.5f, distance[i], in_scatter, transmittance);
      color[i] = color[i] * transmittance + in_scatter;
    }
#else
  const float inv_size = 1.0f / float(grid.froxel_size());
  const size_t n = size_t(x1 - x0);
  // Runs: consecutive pixels with the same columns, at most kLanes each.
  struct Run {
    int x, len;
    Axis ax;
    __m256 lanes;   // the first len lanes
    __m256i valid;  // the same, for masked loads
  };
  std::vector<Run> runs;
  std::vector<float> column_weight(n + kLanes);  // each pixel's ax.a
  for (int x = x0; x < x1; ++x) {
    const Axis ax = axis_at(float(x) + 0.5f, inv_size, grid.nx());
    column_weight[size_t(x - x0)] = ax.a;
    if (!runs.empty() && runs.back().ax.i0 == ax.i0 && runs.back().len < kLanes)
      ++runs.back().len;
    else
      runs.push_back(Run{x - x0, 1, ax, {}, {}});
  }
  for (Run& run : runs) {
    run.lanes = _mm256_cmp_ps(_mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_ps(float(run.len)), _CMP_LT_OQ);
    run.valid = _mm256_castps_si256(run.lanes);
  }
  std::vector<RunStart> starts(runs.size());
  const int nx = grid.nx(), nz = grid.nz();
  for (int y = y0; y < y1; ++y) {
    const Axis ay = axis_at(float(y) + 0.5f, inv_size, grid.ny());
    const __m256 ay_a = _mm256_set1_ps(ay.a), ay_1 = _mm256_set1_ps(1 - ay.a);
    const size_t row = size_t(y) * size_t(width) + size_t(x0);
    if (y + kPrefetchRows < y1) {
      const size_t ahead = row + size_t(kPrefetchRows) * size_t(width);
      prefetch(distance.data() + ahead, n * sizeof(float));
      prefetch(color.data() + ahead, n * sizeof(glm::vec3));
    }
    const size_t row0 = size_t(ay.i0) * nx * nz;
    const size_t row1 = size_t(ay.i1) * nx * nz;
    const float* row_distance = distance.data() + row;
    for (size_t r = 0; r < runs.size(); ++r)
      starts[r] = start_of(grid, _mm256_maskload_ps(row_distance + runs[r].x, runs[r].valid), runs[r].lanes);
    for (size_t r = 0; r < runs.size(); ++r) {
      const Run& run = runs[r];
      if (!starts[r].fog) continue;
      const __m256 a = _mm256_loadu_ps(&column_weight[size_t(run.x)]), a_1 = _mm256_sub_ps(_mm256_set1_ps(1.0f), a);
      // weights_of's products, per lane.
      const RunTaps<Froxels> taps{volume,
                                  {row0 + size_t(run.ax.i0) * nz, row0 + size_t(run.ax.i1) * nz,
                          row1 + size_t(run.ax.i0) * nz, row1 + size_t(run.ax.i1) * nz},
                         {_mm256_mul_ps(a_1, ay_1), _mm256_mul_ps(a, ay_1), _mm256_mul_ps(a_1, ay_a),
                          _mm256_mul_ps(a, ay_a)}};
      composite_run(grid, taps, _mm256_maskload_ps(row_distance + run.x, run.valid), run.lanes, starts[r], run.len,
                    color.data() + row + size_t(run.x));
    }
  }
#endif
}

template <class Froxels>
void composite_fragments(const FroxelGrid& grid, const Froxels& volume, std::span<EdgeFragment> fragments) {
  for (EdgeFragment& e : fragments) {
    glm::vec3 in_scatter;
    float transmittance;
    lookup(grid, volume, e.x, e.y, e.distance, in_scatter, transmittance);
    e.color = e.color * transmittance + in_scatter;
  }
}

}  // namespace

void lookup_fog(const FroxelGrid& g, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  lookup(g, FloatFroxels{volume.data()}, px, py, distance, in_scatter, transmittance);
}

void lookup_fog(const FroxelGrid& g, const std::vector<FixedIntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance) {
  lookup(g, FixedFroxels(volume.data(), g), px, py, distance, in_scatter, transmittance);
}

void composite_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1) {
  composite_rows(grid, FloatFroxels{volume.data()}, distance, color, width, x0, y0, x1, y1);
}

void composite_fog(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1) {
  composite_rows(grid, FixedFroxels(volume.data(), grid), distance, color, width, x0, y0, x1, y1);
}

void composite_fog_fragments(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                             std::span<EdgeFragment> fragments) {
  composite_fragments(grid, FloatFroxels{volume.data()}, fragments);
}

void composite_fog_fragments(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                             std::span<EdgeFragment> fragments) {
  composite_fragments(grid, FixedFroxels(volume.data(), grid), fragments);
}

IntegratedFroxel decode_froxel(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                               size_t index) {
  const FixedFroxels froxels(volume.data(), grid);
  const FixedFroxels::Record r = froxels.record(index);
  const int k = int(index % size_t(grid.nz()));
  return IntegratedFroxel{glm::vec3(r[0], r[1], r[2]), r[3], froxels.extinction(index, k)};
}

}  // namespace cr

// fog.lighting: the sun's shadow visibility per froxel, sampled at one point
// of the froxel per frame. The point is importance sampled along the
// (jittered) ray inside the slice proportionally to the transmittance of the
// homogeneous froxel (seed 002, "closed-form tracking"): with u uniform in
// [0,1),
//   offset = -log(1 - u (1 - exp(-sigma dt))) / sigma,
// whose weight (1 - exp(-sigma dt)) / sigma is applied at integration, so the
// stored value is the transmittance-weighted mean of the visibility over the
// slice. u comes from the 7-frame sequence plus a per-column hash. The sun's
// illuminance is not part of it: it varies slowly along a column (atmospheric
// transmittance with altitude) and integration applies it at the slice
// centre, so the buffer the temporal passes carry is one float per froxel.
//
// A column runs as flat loops over its slices (sample offsets, the batched
// shadow lookups, the sum) that vectorise; only optically thick slices take
// the scalar log. Each froxel's arithmetic is the same sequence of float
// operations as VolumeShadow::visibility and importance_sample_offset, so the
// result does not depend on which path runs. Only the slices from the first
// to the last that scatter are worked on: clear air (above the height fog,
// outside volumes) gets 0 whatever its visibility, so it needs no sample
// point and no shadow lookup. The jitter of each sample is the same for
// every column and is taken once per frame. When the sun has moved since
// the history, each sample is also looked up in last frame's shadow map:
// the difference is the light's own change at that point, which
// reprojection uses to drop history (see froxel_passes.h).
//
// The q15 output (sun_term_format.h) is the same float evaluation, summed
// in a column of scratch and rounded to q15 once per froxel.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/jitter_sequence.h"
#include "fog/sun_term_format.h"

namespace cr {

namespace {

// Per-slice scratch of one job; the sums of a column whose output is not float.
struct ColumnScratch {
  std::vector<float> t, visibility, previous, sum, change_sum;
  explicit ColumnScratch(int nz)
      : t(size_t(nz)), visibility(size_t(nz)), previous(size_t(nz)), sum(size_t(nz)), change_sum(size_t(nz)) {}
};

// FogDensity as flat floats (scattering RGB, extinction): the column loops
// below read it as a 4-way interleave, which vectorises.
static_assert(sizeof(FogDensity) == 4 * sizeof(float));

// Whether froxel k of a flat density column scatters (clear air does not:
// nothing multiplies its light).
inline bool scatters(const float* density, int k) {
  return (density[4 * k] != 0.0f) | (density[4 * k + 1] != 0.0f) | (density[4 * k + 2] != 0.0f);
}

// Importance-sampled points t0[k] + offset of slices [0, n): the thin-slice
// series of importance_sample_offset for every slice (vectorised), then the
// exact log form where a slice is optically thick (a >= 0.05), if any is.
void sample_points(const float* __restrict density, const float* __restrict t0, const float* __restrict dt, float u,
                   int n, float* __restrict t) {
  int thick = 0;
  for (int k = 0; k < n; ++k) {
    const float a = std::max(density[4 * k + 3], 1e-12f) * dt[k];
    t[k] = t0[k] + importance_sample_offset_thin(u, a, dt[k]);
    thick |= int(a >= 0.05f);
  }
  if (!thick) return;
  for (int k = 0; k < n; ++k) {
    const float sigma = std::max(density[4 * k + 3], 1e-12f);
    if (sigma * dt[k] >= 0.05f) t[k] = t0[k] + importance_sample_offset(u, sigma, dt[k]);
  }
}

// out[k] = prior + visibility[k] where the froxel scatters, prior 0 for the
// first sample (the sum starts at 0) and out[k] after; clear air adds 0:
// nothing multiplies its light.
void add_visibility(const float* __restrict density, const float* __restrict visibility, int n, bool first,
                    float* __restrict out) {
  for (int k = 0; k < n; ++k) {
    const float prior = first ? 0.0f : out[k];
    out[k] = prior + (scatters(density, k) ? visibility[k] : 0.0f);
  }
}

// out[k] (+)= |now[k] - then[k]| where the froxel scatters, as add_visibility.
void add_change(const float* __restrict density, const float* __restrict now, const float* __restrict then, int n,
                bool first, float* __restrict out) {
  for (int k = 0; k < n; ++k) {
    const float prior = first ? 0.0f : out[k];
    out[k] = prior + (scatters(density, k) ? std::abs(now[k] - then[k]) : 0.0f);
  }
}

// [first, end) of the slices [0, n) that scatter (first == end: none).
struct ScatteringRange {
  int first = 0, end = 0;
};
ScatteringRange scattering_range(const float* density, int n) {
  ScatteringRange r;
  while (r.first < n && !scatters(density, r.first)) ++r.first;
  r.end = n;
  while (r.end > r.first && !scatters(density, r.end - 1)) --r.end;
  return r;
}

// light_froxels with output values V: float, or q15 codes (Q15SunTerm).
template <class V>
void light_columns(const FroxelView& view, const std::vector<FogDensity>& density, const VolumeShadow& shadow,
                   const JitterInputs& jitter, JobSystem& jobs, std::vector<V>& sun_visibility,
                   const std::function<void(int y0, int y1)>& before_rows, const VolumeShadow* previous,
                   std::vector<V>* light_change, const SettledSamples<V>* settled) {
  constexpr bool kFloat = std::is_same_v<V, float>;
  const FroxelGrid& g = view.grid;
  const PixelRays rays(view.camera, g.width(), g.height());
  sun_visibility.resize(g.count());
  if (!light_change) previous = nullptr;
  // Settled samples belong to a still view; a moving sun lights everything.
  if (previous) settled = nullptr;
  if (previous) light_change->resize(g.count());
  const int nx = g.nx(), nz = g.nz();
  const int samples = std::max(jitter.samples, 1);
  std::vector<float> t0(static_cast<size_t>(nz)), dt(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) {
    t0[size_t(k)] = g.boundary(k);
    dt[size_t(k)] = g.thickness(k);
  }
  const float s = float(g.froxel_size());
  std::vector<FroxelJitter> sample_jitter(static_cast<size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    if (jitter.enabled) sample_jitter[size_t(i)] = froxel_jitter(jitter.frame + i);
    else if (samples > 1) sample_jitter[size_t(i)].depth = (float(i) + 0.5f) / float(samples);
  }
  jobs.parallel_for("fog.lighting", size_t(g.ny()), 1, [&](size_t begin, size_t end) {
    ColumnScratch scratch(nz);
    if (before_rows) before_rows(int(begin), int(end));
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        V* out_column = sun_visibility.data() + g.index(x, y, 0);
        V* change_column = previous ? light_change->data() + g.index(x, y, 0) : nullptr;
        // The sums of the lit slices: in place when the output is float.
        float* out = scratch.sum.data();
        float* change = change_column ? scratch.change_sum.data() : nullptr;
        if constexpr (kFloat) {
          out = out_column;
          change = change_column;
        }
        const float* flat = reinterpret_cast<const float*>(density.data() + g.index(x, y, 0));
        const int n = view.lit_slices[size_t(y) * nx + x];
        ScatteringRange lit = scattering_range(flat, n);
        // Outside the range the froxels are clear air: 0.
        for (int k = 0; k < lit.first; ++k) out_column[k] = V(0);
        for (int k = lit.end; k < n; ++k) out_column[k] = V(0);
        if (settled) {
          // Settled froxels take their settled sample; the rest are lit.
          const SliceSpan span = (*settled->spans)[size_t(y) * nx + x];
          const V* value = settled->values->data() + g.index(x, y, 0);
          const int first = std::max(lit.first, int(span.first)), end = std::min(lit.end, int(span.end));
          if (first >= end) {
            std::copy(value + lit.first, value + lit.end, out_column + lit.first);
            continue;
          }
          std::copy(value + lit.first, value + first, out_column + lit.first);
          std::copy(value + end, value + lit.end, out_column + end);
          lit = ScatteringRange{first, end};
        }
        if (change_column) {
          std::fill(change_column, change_column + lit.first, V(0));
          std::fill(change_column + lit.end, change_column + n, V(0));
        }
        if (lit.first == lit.end) continue;
        const int m = lit.end - lit.first;
        const float* medium = flat + 4 * lit.first;
        const glm::vec2 center_px = g.column_center_px(x, y);
        const float hash = column_hash(x, y);
        for (size_t i = 0; i < sample_jitter.size(); ++i) {
          const FroxelJitter& j = sample_jitter[i];
          // fmod(x, 1) for x = hash + depth in [0, 2) without the libm call:
          // x - 1 is exact there (Sterbenz), so the bits are fmod's.
          const float wrapped = hash + j.depth;
          const float u = wrapped >= 1.0f ? wrapped - 1.0f : wrapped;
          const glm::vec3 dir = rays.direction(center_px.x + j.lateral.x * s, center_px.y + j.lateral.y * s);
          float* t = scratch.t.data();
          float* vis = scratch.visibility.data();
          sample_points(medium, t0.data() + lit.first, dt.data() + lit.first, u, m, t);
          shadow.visibility(shadow.ray(glm::vec3(0.0f), dir), t, m, vis);
          add_visibility(medium, vis, m, i == 0, out + lit.first);
          if (change) {
            float* then = scratch.previous.data();
            previous->visibility(previous->ray(glm::vec3(0.0f), dir), t, m, then);
            add_change(medium, vis, then, m, i == 0, change + lit.first);
          }
        }
        if (samples > 1)
          for (int k = lit.first; k < lit.end; ++k) {
            out[k] /= float(samples);
            if (change) change[k] /= float(samples);
          }
        if constexpr (!kFloat) {
          for (int k = lit.first; k < lit.end; ++k) out_column[k] = Q15SunTerm::encode(out[k]);
          if (change)
            for (int k = lit.first; k < lit.end; ++k) change_column[k] = Q15SunTerm::encode(change[k]);
        }
      }
  });
}

}  // namespace

void light_froxels(const FroxelView& view, const std::vector<FogDensity>& density, const VolumeShadow& shadow,
                   const JitterInputs& jitter, JobSystem& jobs, std::vector<float>& sun_visibility,
                   const std::function<void(int y0, int y1)>& before_rows, const VolumeShadow* previous,
                   std::vector<float>* light_change, const SettledSamples<float>* settled) {
  light_columns(view, density, shadow, jitter, jobs, sun_visibility, before_rows, previous, light_change, settled);
}

void light_froxels(const FroxelView& view, const std::vector<FogDensity>& density, const VolumeShadow& shadow,
                   const JitterInputs& jitter, JobSystem& jobs, std::vector<uint16_t>& sun_visibility,
                   const std::function<void(int y0, int y1)>& before_rows, const VolumeShadow* previous,
                   std::vector<uint16_t>* light_change, const SettledSamples<uint16_t>* settled) {
  light_columns(view, density, shadow, jitter, jobs, sun_visibility, before_rows, previous, light_change, settled);
}

}  // namespace cr

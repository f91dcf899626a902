// fog.integrate: front-to-back integration along each column. Inside a froxel
// the medium is homogeneous (extinction sigma, scattering sigma_s) and the
// source J = sigma_s (phase * E_sun * visibility + ambient) is constant, so one
// slice of length dt adds T * J (1 - exp(-sigma dt)) / sigma and multiplies T
// by exp(-sigma dt) (exact, no step-size error). The phase function, the
// phase-convolved SH ambient and the sun's illuminance use the column's centre
// direction; the illuminance varies slowly (atmospheric transmittance with
// altitude), so it is evaluated at the column's first and last slice centres
// (one sun_at batch per row of columns) and interpolated in distance.
//
// In a still view most of the visibility is the same from frame to frame
// (fully lit or shadowed air, where every sample agrees), and a column's
// volume up to its first changed slice is what it was: incremental
// integration starts each column there.
//
// The fixed-point recurrence (FixedIntegratedFroxel, fixed_volume.h) evaluates the
// same terms in float and quantises them: each slice's optical depth in log2
// units as Q16.16, summed with saturation (transmittance cannot wrap or
// rise), the transmittance T = exp2_neg_q15(depth), and each slice's source
// over its extinction as q15 of the column's largest (per channel). A slice
// adds source * (T_before - T_after): a q15 x q15 product, summed exactly in
// 32 bits (at most 32767^2 < 2^30), with no rounding along the column. Each
// froxel stores the sum as radiance in hdr16 and the depth in Q5.11. Its
// state is wider than what it stores, so a changed column is integrated
// whole (unchanged columns keep their volume).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include <immintrin.h>

#include "fog/fixed_volume.h"
#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/phase_function.h"
#include "fog/sun_term_format.h"

namespace cr {

namespace {

// Per-slice terms of one column, independent of each other (flat loops over
// SoA scratch, vectorised with the same float operations per lane):
// opacity 1 - exp(-x) and the slice's weight (1 - exp(-x)) / sigma (its limit
// dt for x -> 0; the division runs for every slice, on a sigma kept off zero,
// so the loop has no branch), and the source sigma_s (phase E_sun V + ambient)
// split into RGB.
struct ColumnTerms {
  std::vector<float> opacity, weight, r, g, b;
  explicit ColumnTerms(int nz)
      : opacity(size_t(nz)), weight(size_t(nz)), r(size_t(nz)), g(size_t(nz)), b(size_t(nz)) {}
};

struct ColumnLight {
  glm::vec3 e0, de;  // sun illuminance at t_first and its slope in t
  float t_first;
  float phase;
  glm::vec3 ambient;
};

// One channel of the source: scattering (illuminance at `along` past
// t_first x visibility x phase + ambient).
inline float source_of(float scattering, float e0, float de, float along, float vp, float ambient) {
  return scattering * (std::max(e0 + de * along, 0.0f) * vp + ambient);
}

void column_terms(const FogDensity* __restrict d, const float* __restrict visibility, const float* __restrict dt,
                  const float* __restrict center, int n, const ColumnLight& light, ColumnTerms& out) {
  float* __restrict opacity = out.opacity.data();
  float* __restrict weight = out.weight.data();
  float* __restrict r = out.r.data();
  float* __restrict g = out.g.data();
  float* __restrict b = out.b.data();
  const glm::vec3 e0 = light.e0, de = light.de, ambient = light.ambient;
  const float t_first = light.t_first, phase = light.phase;
  // FogDensity as flat floats (scattering RGB, extinction), so the loads
  // vectorise as a 4-way interleave.
  static_assert(sizeof(FogDensity) == 4 * sizeof(float));
  const float* __restrict m = reinterpret_cast<const float*>(d);
  for (int k = 0; k < n; ++k) {
    const float sigma = m[4 * k + 3];
    const float optical = sigma * dt[k];
    const float o = opacity_of(optical);
    opacity[k] = o;
    const float ratio = o / std::max(sigma, 1e-30f);
    weight[k] = optical > 1e-6f ? ratio : dt[k];
    const float along = center[k] - t_first;
    const float vp = visibility[k] * phase;
    r[k] = source_of(m[4 * k], e0.x, de.x, along, vp, ambient.x);
    g[k] = source_of(m[4 * k + 1], e0.y, de.y, along, vp, ambient.y);
    b[k] = source_of(m[4 * k + 2], e0.z, de.z, along, vp, ambient.z);
  }
}

// The first k < n where a[k] and b[k] differ bit for bit (n if none), from
// slice k0 (blocks before it are known to agree).
template <class V>
int first_difference_from(const V* a, const V* b, int k0, int n) {
  using Bits = std::conditional_t<sizeof(V) == 4, uint32_t, uint16_t>;
  for (int k = k0; k < n; ++k)
    if (std::bit_cast<Bits>(a[k]) != std::bit_cast<Bits>(b[k])) return k;
  return n;
}

// The same, 32 bytes (8 floats or 16 codes) to a compare where the CPU has AVX2.
template <class V>
__attribute__((target("avx2"))) int first_difference_avx2(const V* a, const V* b, int n) {
  constexpr int kBlock = 32 / int(sizeof(V));
  int k = 0;
  for (; k + kBlock <= n; k += kBlock) {
    const __m256i x = _mm256_xor_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + k)),
                                       _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + k)));
    if (!_mm256_testz_si256(x, x)) break;
  }
  return first_difference_from(a, b, k, n);
}

template <class V>
int first_difference(const V* a, const V* b, int n) {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2 ? first_difference_avx2(a, b, n) : first_difference_from(a, b, 0, n);
}

// The float recurrence of a column from slice s (the volume before s kept).
struct FloatColumn {
  using Visibility = float;
  using Froxel = IntegratedFroxel;
  static constexpr bool kResumesInside = true;  // a changed column continues from its first change
  ColumnTerms terms;
  explicit FloatColumn(int nz) : terms(nz) {}

  void integrate(const FogDensity* column, const float* visibility, const float* dt, const float* center, int s,
                 int n, int nz, const ColumnLight& light, IntegratedFroxel* volume) {
    const FogDensity* d = column + s;
    // The terms run to a whole number of 8-slice blocks (within the
    // column): the vectorised loop then has no scalar remainder, and the
    // slices past n, stale but finite, are computed and never read.
    const int whole_blocks = std::min((n - s + 7) / 8 * 8, nz - s);
    column_terms(d, visibility + s, dt + s, center + s, whole_blocks, light, terms);
    // The front-to-back recurrence, from the volume at slice s - 1.
    IntegratedFroxel* out = volume + s;
    glm::vec3 in_scatter = s > 0 ? out[-1].in_scatter : glm::vec3(0.0f);
    float transmittance = s > 0 ? out[-1].transmittance : 1.0f;
    for (int k = 0; k < n - s; ++k) {
      const float tw = transmittance * terms.weight[size_t(k)];
      in_scatter.x += terms.r[size_t(k)] * tw;
      in_scatter.y += terms.g[size_t(k)] * tw;
      in_scatter.z += terms.b[size_t(k)] * tw;
      transmittance *= 1.0f - terms.opacity[size_t(k)];
      out[k] = IntegratedFroxel{in_scatter, transmittance, d[k].extinction};
    }
  }
};

// Largest Q16.16 log2 optical depth: 32, where the stored Q5.11 code
// saturates (the transmittance is 0 beyond 16). A slice's depth and the sum
// saturate there, so neither can wrap.
constexpr uint32_t kDepthCap = uint32_t(32) << 16;
constexpr float kDepthPerNeper = 65536.0f / 0.693147181f;  // Q16.16 log2 units per unit of optical depth

// A slice's optical depth in Q16.16 log2 units, rounded to nearest,
// saturated at kDepthCap (NaN -> 0). Branch-free, so the terms vectorise.
inline uint32_t depth_q16_16(float optical) {
  const float x = optical * kDepthPerNeper;
  return uint32_t(int32_t(std::nearbyint(std::min(x > 0.0f ? x : 0.0f, float(kDepthCap)))));
}

// The source over extinction per channel: the slice's in-scatter per unit of
// 1 - transmittance, never negative; vp (visibility times phase) is
// overwritten with the slice's optical depth.
void sources(const float* __restrict m, float* __restrict vp, const float* __restrict dt,
             const float* __restrict center, int n, const ColumnLight& light, float* __restrict r,
             float* __restrict g, float* __restrict b) {
  const glm::vec3 e0 = light.e0, de = light.de, ambient = light.ambient;
  const float t_first = light.t_first;
  for (int k = 0; k < n; ++k) {
    const float sigma = m[4 * k + 3];
    const float per_extinction = sigma > 0.0f ? 1.0f / sigma : 0.0f;
    const float along = center[k] - t_first;
    r[k] = std::max(source_of(m[4 * k], e0.x, de.x, along, vp[k], ambient.x), 0.0f) * per_extinction;
    g[k] = std::max(source_of(m[4 * k + 1], e0.y, de.y, along, vp[k], ambient.y), 0.0f) * per_extinction;
    b[k] = std::max(source_of(m[4 * k + 2], e0.z, de.z, along, vp[k], ambient.z), 0.0f) * per_extinction;
    vp[k] = sigma * dt[k];
  }
}

// The fixed-point recurrence of a whole column (see the top of the file), as
// flat loops over the slices: the float terms, the shares, the depth's
// prefix sum and transmittance, then the in-scatter sums.
struct FixedColumn {
  using Visibility = uint16_t;
  using Froxel = FixedIntegratedFroxel;
  static constexpr bool kResumesInside = false;  // a changed column starts over
  // Per slice: the Q16.16 log2 optical depth (then its sum from the near
  // plane), T as q15, and per channel the scattered radiance over
  // extinction and the same as q15 of the column's largest.
  std::vector<uint32_t> depth, transmittance;
  std::vector<float> optical;  // the visibility times the phase, then the optical depth
  std::vector<float> source[3];
  std::vector<uint16_t> share[3];
  std::vector<uint32_t> in_scatter[3];  // the exact sums
  explicit FixedColumn(int nz) : depth(size_t(nz)), transmittance(size_t(nz)), optical(size_t(nz)) {
    for (int c = 0; c < 3; ++c) {
      source[c].resize(size_t(nz));
      share[c].resize(size_t(nz));
      in_scatter[c].resize(size_t(nz));
    }
  }

  void integrate(const FogDensity* column, const uint16_t* visibility, const float* dt, const float* center, int,
                 int n, int, const ColumnLight& light, FixedIntegratedFroxel* out) {
    static_assert(sizeof(FogDensity) == 4 * sizeof(float));
    const float* __restrict m = reinterpret_cast<const float*>(column);
    uint32_t* __restrict d = depth.data();
    float* __restrict r = source[0].data();
    float* __restrict g = source[1].data();
    float* __restrict b = source[2].data();
    // Loops of one element size each, so they vectorise.
    const float phase = light.phase;
    float* __restrict vp = optical.data();
    for (int k = 0; k < n; ++k) vp[k] = Q15SunTerm::decode(visibility[k]) * phase;
    sources(m, vp, dt, center, n, light, r, g, b);
    for (int k = 0; k < n; ++k) d[k] = depth_q16_16(vp[k]);
    // Shares of the column's largest source per channel, so a dark column
    // keeps its precision; radiance per unit of the exact sums below.
    float scale[3];
    for (int c = 0; c < 3; ++c) {
      const float* __restrict src = source[c].data();
      uint16_t* __restrict q = share[c].data();
      // The sources are not negative: as unsigned integers their bits order
      // as their values, and an integer maximum vectorises.
      uint32_t largest_bits = 0;
      for (int k = 0; k < n; ++k) largest_bits = std::max(largest_bits, std::bit_cast<uint32_t>(src[k]));
      const float largest = std::bit_cast<float>(largest_bits);
      const float per_largest = largest > 0.0f ? 1.0f / largest : 0.0f;
      for (int k = 0; k < n; ++k) q[k] = fx::encode_q15(src[k] * per_largest);
      scale[c] = largest * 0x1p-30f;
    }
    // Depth from the near plane, saturating; T is exp2_neg_q15 of it, so it
    // never rises: each step T_before - T_after >= 0.
    uint32_t sum = 0;
    for (int k = 0; k < n; ++k) d[k] = sum = std::min(sum + d[k], kDepthCap);
    uint32_t* __restrict t = transmittance.data();
    for (int k = 0; k < n; ++k) t[k] = fx::exp2_neg_q15(d[k]);
    // Exact sums of share x step: each stays below 32767^2 < 2^30.
    const uint16_t* __restrict qr = share[0].data();
    const uint16_t* __restrict qg = share[1].data();
    const uint16_t* __restrict qb = share[2].data();
    uint32_t* __restrict lr = in_scatter[0].data();
    uint32_t* __restrict lg = in_scatter[1].data();
    uint32_t* __restrict lb = in_scatter[2].data();
    uint32_t before = fx::exp2_neg_q15(0), sum_r = 0, sum_g = 0, sum_b = 0;
    for (int k = 0; k < n; ++k) {
      const uint32_t step = before - t[k];
      before = t[k];
      lr[k] = sum_r += qr[k] * step;
      lg[k] = sum_g += qg[k] * step;
      lb[k] = sum_b += qb[k] * step;
    }
    // The records: radiance in hdr16, the depth in Q5.11.
    for (int k = 0; k < n; ++k) {
      FixedIntegratedFroxel& f = out[k];
      f.in_scatter[0] = fx::encode_hdr16(float(lr[k]) * scale[0]);
      f.in_scatter[1] = fx::encode_hdr16(float(lg[k]) * scale[1]);
      f.in_scatter[2] = fx::encode_hdr16(float(lb[k]) * scale[2]);
      f.optical_depth = uint16_t(std::min<uint32_t>((d[k] + (1u << (kOpticalDepthShift - 1))) >> kOpticalDepthShift,
                                                    0xFFFF));
    }
  }
};

}  // namespace

std::vector<glm::vec3> sun_knots(const FroxelView& view, const MediumLighting& lighting, JobSystem& jobs) {
  if (!lighting.light || !lighting.light->sun_at) return {};
  const FroxelGrid& g = view.grid;
  const int nx = g.nx(), knots = sun_knots_per_row(nx);
  const float t_first = g.center(0), t_last = g.center(g.nz() - 1);
  std::vector<glm::vec3> out(size_t(g.ny()) * size_t(knots) * 2);
  jobs.parallel_for("fog.sun_knots", size_t(g.ny()), 1, [&](size_t begin, size_t end) {
    std::vector<glm::vec3> ends(size_t(knots) * 2);
    for (size_t y = begin; y < end; ++y) {
      for (int i = 0; i < knots; ++i) {
        const glm::vec3 dir = view.directions[y * nx + size_t(std::min(i * kSunStride, nx - 1))];
        ends[size_t(i) * 2] = glm::vec3(lighting.camera_position + glm::dvec3(dir * t_first));
        ends[size_t(i) * 2 + 1] = glm::vec3(lighting.camera_position + glm::dvec3(dir * t_last));
      }
      // One sun_at batch per row.
      lighting.light->sun_at(ends.data(), out.data() + y * ends.size(), ends.size());
    }
  });
  return out;
}

namespace {

// integrate_columns over rows of columns, each column by a Column
// (FloatColumn, FixedColumn): the sun's illuminance, phase and ambient per
// column, and where each column starts.
template <class Column, class V = typename Column::Visibility, class Froxel = typename Column::Froxel>
size_t integrate_rows(const FroxelView& view, const std::vector<FogDensity>& density,
                      const std::vector<V>& sun_visibility, const MediumLighting& lighting,
                      const std::vector<glm::vec3>& knots, JobSystem& jobs, std::vector<Froxel>& volume,
                      const IncrementalIntegration<V>& incremental) {
  const FroxelGrid& g = view.grid;
  volume.resize(g.count());
  V* previous = nullptr;
  if (incremental.previous) {
    incremental.previous->resize(g.count());
    previous = incremental.previous->data();
  }
  const bool resume = previous && incremental.continue_volume;
  std::vector<size_t> integrated_per_row(size_t(g.ny()), 0);
  const int nx = g.nx(), nz = g.nz();
  std::vector<float> dt(static_cast<size_t>(nz)), center(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) {
    dt[size_t(k)] = g.thickness(k);
    center[size_t(k)] = g.center(k);
  }
  const float t_first = g.center(0), t_last = g.center(nz - 1);
  const std::array<float, 3> zonal = phase_zonal_coefficients(lighting.phase, lighting.anisotropy);
  const size_t row_knots = size_t(sun_knots_per_row(nx)) * 2;
  jobs.parallel_for("fog.integrate", size_t(g.ny()), 1, [&](size_t begin, size_t end) {
    Column column(nz);
    // Per row of columns: the sun's illuminance at each column's ends,
    // lerped between the knots.
    std::vector<glm::vec3> e(size_t(nx) * 2, lighting.sun_illuminance);
    std::vector<int> start(static_cast<size_t>(nx), 0);  // 0 without a volume to continue
    for (int y = int(begin); y < int(end); ++y) {
      size_t integrated = 0;  // stored once per row (rows of other jobs share cache lines)
      if (!knots.empty()) {
        const glm::vec3* knot_e = knots.data() + size_t(y) * row_knots;
        for (int x = 0; x < nx; ++x) {
          const int i = x / kSunStride, x0 = i * kSunStride, x1 = std::min(x0 + kSunStride, nx - 1);
          const float a = x1 > x0 ? float(x - x0) / float(x1 - x0) : 0.0f;
          for (size_t j = 0; j < 2; ++j) {
            const glm::vec3 lo = knot_e[size_t(i) * 2 + j], hi = knot_e[size_t(i + 1) * 2 + j];
            e[size_t(x) * 2 + j] = lo + (hi - lo) * a;
          }
        }
      }
      // Where each column of the row starts (its first changed slice when
      // resuming; 0 for a changed column of a Column that starts over).
      // Resumed columns read their density and the volume from there, which
      // the hardware prefetcher cannot guess: both are requested for the
      // whole row first.
      for (int x = 0; resume && x < nx; ++x) {
        const int n = view.active_slices[size_t(y) * nx + x];
        const size_t base = g.index(x, y, 0);
        int s = first_difference(sun_visibility.data() + base, previous + base, n);
        if (!Column::kResumesInside && s < n) s = 0;
        start[size_t(x)] = s;
        if (s == n) continue;
        const char* from = reinterpret_cast<const char*>(density.data() + base + s);
        const char* to = reinterpret_cast<const char*>(density.data() + base + n);
        for (const char* p = from; p < to; p += 64) __builtin_prefetch(p);
        if (s > 0) __builtin_prefetch(volume.data() + base + s - 1);  // the state it continues from
      }
      for (int x = 0; x < nx; ++x) {
        const size_t c = size_t(y) * nx + x;
        const int n = view.active_slices[c];
        const int s = start[size_t(x)];  // slices [0, s) keep their volume
        if (s == n) continue;
        const glm::vec3 dir = view.directions[c];
        ColumnLight light;
        light.e0 = e[size_t(x) * 2];
        light.de = nz > 1 ? (e[size_t(x) * 2 + 1] - light.e0) / (t_last - t_first) : glm::vec3(0.0f);
        light.t_first = t_first;
        light.phase = evaluate_phase(lighting.phase, glm::dot(dir, lighting.sun_direction), lighting.anisotropy);
        light.ambient = phase_convolved_ambient(lighting.ambient_sh, zonal, dir);
        const size_t base = g.index(x, y, 0);
        const V* visibility = sun_visibility.data() + base;
        if (previous) std::copy(visibility + s, visibility + n, previous + base + size_t(s));
        integrated += size_t(n - s);
        column.integrate(density.data() + base, visibility, dt.data(), center.data(), s, n, nz, light,
                         volume.data() + base);
      }
      integrated_per_row[size_t(y)] = integrated;
    }
  });
  size_t integrated = 0;
  for (size_t r : integrated_per_row) integrated += r;
  return integrated;
}

}  // namespace

size_t integrate_columns(const FroxelView& view, const std::vector<FogDensity>& density,
                         const std::vector<float>& sun_visibility, const MediumLighting& lighting,
                         const std::vector<glm::vec3>& knots, JobSystem& jobs, std::vector<IntegratedFroxel>& volume,
                         const IncrementalIntegration<float>& incremental) {
  return integrate_rows<FloatColumn>(view, density, sun_visibility, lighting, knots, jobs, volume, incremental);
}

size_t integrate_columns(const FroxelView& view, const std::vector<FogDensity>& density,
                         const std::vector<uint16_t>& sun_visibility, const MediumLighting& lighting,
                         const std::vector<glm::vec3>& knots, JobSystem& jobs,
                         std::vector<FixedIntegratedFroxel>& volume,
                         const IncrementalIntegration<uint16_t>& incremental) {
  return integrate_rows<FixedColumn>(view, density, sun_visibility, lighting, knots, jobs, volume, incremental);
}

}  // namespace cr

#pragma once
// The per-sample LUT work of shading a march, shared by the per-ray paths
// (scattering_march.cpp) and the froxel column (froxel_column.cpp): the sun
// transmittance and multiple-scattering lookup coordinates of a sample, and
// the sample's contribution from the packed (rgb + pad) texels. Both are
// TransmittanceLut::sun() / sample_bilinear() and shade_split()'s sums with
// the same operations in the same order, so every path gives the same bits.
#include <cstddef>

#include "atmosphere/float4.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

// Lookup coordinates of one sample for the sun cosine mu = (r0_mu_s + t nu) / r
// at the sample (row: its transmittance row, inv_r: 1 / its radius).
// Branch-free (the shadow is a visibility factor of 0), so loops over it vectorize.
inline void sample_coordinate(const TransmittanceRow& row, int t_width, int ms_width, float r0_mu_s, float t,
                              float inv_r, float nu, int& t_x0, int& t_x1, float& t_w, float& sun_visible, int& ms_x0,
                              int& ms_x1, float& ms_w) {
  float mu = (r0_mu_s + t * nu) * inv_r;
  mu = mu < -1.0f ? -1.0f : (1.0f < mu ? 1.0f : mu);
  sun_lookup(row, t_width, mu, t_x0, t_x1, t_w, sun_visible);
  // Multiple-scattering LUT column: MultiScatteringLut::sample()'s
  const float ms_last = float(ms_width - 1);
  float mx = MultiScatteringMapping::to_unit(mu) * ms_last;
  mx = mx > 0.0f ? (mx < ms_last ? mx : ms_last) : 0.0f;
  const int mx0 = int(mx) < ms_width - 1 ? int(mx) : ms_width - 1;
  ms_x0 = mx0;
  ms_x1 = mx0 + 1 < ms_width - 1 ? mx0 + 1 : ms_width - 1;
  ms_w = mx - float(mx0);
}

struct PackedLuts {
  const float* transmittance;
  int transmittance_width;
  const float* multiscattering;
  int multiscattering_width;
  PackedLuts(const TransmittanceLut& t, const MultiScatteringLut& ms)
      : transmittance(t.packed()),
        transmittance_width(t.image().width),
        multiscattering(ms.packed()),
        multiscattering_width(ms.image().width) {}
};

// Adds one sample's single (Rayleigh, Mie unphased) and multiple scattering
// at its lookup coordinates (t_y, ms_y: the rows) to rest and mie; w_*: the
// sample's weights (throughput * scattering * segment integral).
inline void add_sample(const PackedLuts& p, const LutCoord& t_y, const LutCoord& ms_y, int t_x0, int t_x1, float t_w,
                       float sun_visible, int ms_x0, int ms_x1, float ms_w, float phase_r, const Float4& w_rayleigh,
                       const Float4& w_mie, const Float4& w_ms, Float4& rest, Float4& mie) {
  const Float4 sun =
      bilinear4(p.transmittance, p.transmittance_width, t_x0, t_x1, t_w, t_y.i0, t_y.i1, t_y.w) * splat4(sun_visible);
  const Float4 psi =
      bilinear4(p.multiscattering, p.multiscattering_width, ms_x0, ms_x1, ms_w, ms_y.i0, ms_y.i1, ms_y.w);
  rest += sun * w_rayleigh * splat4(phase_r) + psi * w_ms;
  mie += sun * w_mie;
}

}  // namespace cr

#pragma once
// The per-sample LUT work of shading a march, shared by the per-ray paths
// (scattering_march.cpp) and the froxel column (froxel_column.cpp): the sun
// transmittance and multiple-scattering lookup coordinates of a sample, and
// the sample's contribution from the packed (rgb + pad) texels. Both are
// TransmittanceLut::sun() / sample_bilinear() and shade_split()'s sums with
// the same operations in the same order, so every path gives the same bits.
#include <cmath>
#include <cstddef>

#include "atmosphere/float4.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

// The view direction at a sample in the multiple-scattering moments' frame
// (multiscattering_lut.h): x towards the sun horizontally, y up; the factors
// of the quadratic moment (v^T A v = A_xx q_xx + A_yy q_yy + A_xy q_xy) and
// the first moment's (v_x, v_y).
struct MsView {
  float q_xx, q_yy, q_xy, v_x, v_y;
};

// v_y from the ray (r0_mu: r0 * its zenith cosine), v_x from nu = v.sun and
// the sun's cosine mu there. Selects, no branch: loops over it vectorize.
inline MsView ms_view(float r0_mu, float t, float inv_r, float nu, float mu) {
  float v_y = (r0_mu + t) * inv_r;
  v_y = v_y < -1.0f ? -1.0f : (1.0f < v_y ? 1.0f : v_y);
  const float sin2 = 1.0f - mu * mu;
  // The sun at the local zenith or nadir: the field is symmetric about up and any x will do.
  const float v_x = sin2 > 1e-8f ? (nu - mu * v_y) / std::sqrt(sin2 > 1e-8f ? sin2 : 1.0f) : 0.0f;
  const float z2 = 1.0f - v_x * v_x - v_y * v_y;
  const float v_z2 = z2 > 0.0f ? z2 : 0.0f;
  return {v_x * v_x - v_z2, v_y * v_y - v_z2, 2.0f * v_x * v_y, v_x, v_y};
}

// Lookup coordinates of one sample for the sun cosine mu = (r0_mu_s + t nu) / r
// at the sample (row: its transmittance row, inv_r: 1 / its radius), and the
// view's moment factors (r0_mu: see ms_view).
// Branch-free (the shadow is a visibility factor of 0), so loops over it vectorize.
inline void sample_coordinate(const TransmittanceRow& row, int t_width, int ms_width, float r0_mu, float r0_mu_s,
                              float t, float inv_r, float nu, int& t_x0, int& t_x1, float& t_w, float& sun_visible,
                              int& ms_x0, int& ms_x1, float& ms_w, MsView& view) {
  float mu = (r0_mu_s + t * nu) * inv_r;
  mu = mu < -1.0f ? -1.0f : (1.0f < mu ? 1.0f : mu);
  view = ms_view(r0_mu, t, inv_r, nu, mu);
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
  const float* moment[kMsMomentCount];
  Float4 mie_quadratic_ratio;
  PackedLuts(const TransmittanceLut& t, const MultiScatteringLut& ms)
      : transmittance(t.packed()),
        transmittance_width(t.image().width),
        multiscattering(ms.packed()),
        multiscattering_width(ms.image().width),
        mie_quadratic_ratio(splat4(ms.mie_quadratic_ratio())) {
    for (int k = 0; k < kMsMomentCount; ++k) moment[k] = ms.moment(k);
  }
};

// Adds one sample's single (Rayleigh, Mie unphased) and multiple scattering
// at its lookup coordinates (t_y, ms_y: the rows) to rest and mie; w_*: the
// sample's weights (throughput * scattering * segment integral). The multiple
// scattering is Psi plus each phase's share of the moments (view: ms_view).
inline void add_sample(const PackedLuts& p, const LutCoord& t_y, const LutCoord& ms_y, int t_x0, int t_x1, float t_w,
                       float sun_visible, int ms_x0, int ms_x1, float ms_w, const MsView& view, float phase_r,
                       const Float4& w_rayleigh, const Float4& w_mie, const Float4& w_ms, Float4& rest, Float4& mie) {
  const Float4 sun =
      bilinear4(p.transmittance, p.transmittance_width, t_x0, t_x1, t_w, t_y.i0, t_y.i1, t_y.w) * splat4(sun_visible);
  auto ms = [&](const float* texels) {
    return bilinear4(texels, p.multiscattering_width, ms_x0, ms_x1, ms_w, ms_y.i0, ms_y.i1, ms_y.w);
  };
  const Float4 psi = ms(p.multiscattering);
  const Float4 quadratic = ms(p.moment[kMsQuadXX]) * splat4(view.q_xx) + ms(p.moment[kMsQuadYY]) * splat4(view.q_yy) +
                           ms(p.moment[kMsQuadXY]) * splat4(view.q_xy);
  const Float4 first = ms(p.moment[kMsFirstX]) * splat4(view.v_x) + ms(p.moment[kMsFirstY]) * splat4(view.v_y);
  // The moments are a truncated expansion: strong anisotropy (|g| near 1)
  // can take the sum below zero, where no light is.
  const Float4 multiple = psi * w_ms + quadratic * w_rayleigh + (quadratic * p.mie_quadratic_ratio + first) * w_mie;
  rest += sun * w_rayleigh * splat4(phase_r) + max4(multiple, Float4{});
  mie += sun * w_mie;
}

}  // namespace cr

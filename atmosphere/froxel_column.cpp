#include "atmosphere/froxel_column.h"

#include <vector>

#include "atmosphere/float4.h"
#include "atmosphere/march_lookups.h"
#include "atmosphere/phase_functions.h"

namespace cr {

namespace {

// Lookup coordinates of every step, one array per quantity, one thread's.
struct StepCoordinates {
  std::vector<int> t_x0, t_x1, t_y0, t_y1, ms_x0, ms_x1, ms_y0, ms_y1;
  std::vector<float> t_w, t_wy, visible, ms_w, ms_wy, q_xx, q_yy, q_xy, v_x, v_y;
  void resize(size_t n) {
    for (auto* v : {&t_x0, &t_x1, &t_y0, &t_y1, &ms_x0, &ms_x1, &ms_y0, &ms_y1}) v->resize(n);
    for (auto* v : {&t_w, &t_wy, &visible, &ms_w, &ms_wy, &q_xx, &q_yy, &q_xy, &v_x, &v_y}) v->resize(n);
  }
};

// accumulate()'s per-step row, radius and multiple-scattering row, and
// sample_coordinate(), for n steps at once. Restrict pointers, selects and
// no call: it vectorizes; out of line so that GCC keeps the restricts.
__attribute__((noinline)) void step_coordinates(const AtmosphereLuts& luts, float r0_mu, float r0_mu_s, float nu,
                                                size_t n,
                                                const float* __restrict t, const float* __restrict h,
                                                int* __restrict t_x0, int* __restrict t_x1, float* __restrict t_w,
                                                int* __restrict t_y0, int* __restrict t_y1, float* __restrict t_wy,
                                                float* __restrict visible, int* __restrict ms_x0,
                                                int* __restrict ms_x1, float* __restrict ms_w,
                                                int* __restrict ms_y0, int* __restrict ms_y1,
                                                float* __restrict ms_wy, float* __restrict q_xx,
                                                float* __restrict q_yy, float* __restrict q_xy,
                                                float* __restrict v_x, float* __restrict v_y) {
  const float R = float(luts.model.bottom_radius);
  const float top = float(luts.model.atmosphere_height());
  const int ms_width = luts.multiscattering.image().width, ms_height = luts.multiscattering.image().height;
  const int t_width = luts.transmittance.image().width;
  const float ms_scale = float(ms_height - 1) / top;
  for (size_t k = 0; k < n; ++k) {
    const float inv_r = 1.0f / (R + h[k]);
    const TransmittanceRow row = luts.transmittance.row(h[k]);
    t_y0[k] = row.y.i0;
    t_y1[k] = row.y.i1;
    t_wy[k] = row.y.w;
    const LutCoord ms_y = lut_coord((top < h[k] ? top : h[k]) * ms_scale, ms_height);
    ms_y0[k] = ms_y.i0;
    ms_y1[k] = ms_y.i1;
    ms_wy[k] = ms_y.w;
    MsView view;
    sample_coordinate(row, t_width, ms_width, r0_mu, r0_mu_s, t[k], inv_r, nu, t_x0[k], t_x1[k], t_w[k],
                      visible[k], ms_x0[k], ms_x1[k], ms_w[k], view);
    q_xx[k] = view.q_xx;
    q_yy[k] = view.q_yy;
    q_xy[k] = view.q_xy;
    v_x[k] = view.v_x;
    v_y[k] = view.v_y;
  }
}

}  // namespace

void shade_runs(const AtmosphereLuts& luts, const MarchSteps& steps, float h0, float mu, float mu_s, float nu,
                size_t run, ShadedRay* shaded, glm::vec3* transmittance) {
  const size_t n = steps.t.size();
  thread_local StepCoordinates c;
  c.resize(n);
  const float r0 = float(luts.model.bottom_radius) + h0;  // MarchedRay::r0
  step_coordinates(luts, r0 * mu, r0 * mu_s, nu, n, steps.t.data(), steps.h.data(), c.t_x0.data(), c.t_x1.data(), c.t_w.data(),
                   c.t_y0.data(), c.t_y1.data(), c.t_wy.data(), c.visible.data(), c.ms_x0.data(), c.ms_x1.data(),
                   c.ms_w.data(), c.ms_y0.data(), c.ms_y1.data(), c.ms_wy.data(), c.q_xx.data(), c.q_yy.data(),
                   c.q_xy.data(), c.v_x.data(), c.v_y.data());
  const PackedLuts packed(luts.transmittance, luts.multiscattering);
  const float phase_r = rayleigh_phase(nu);
  const Float4 rayleigh = to_float4(luts.model.rayleigh_scattering), mie = to_float4(luts.model.mie_scattering);
  for (size_t begin = 0, r = 0; begin < n; begin += run, ++r) {
    // accumulate()'s weights and throughput (glm's lane-wise operations on rgb + pad), then add_sample.
    Float4 throughput = splat4(1.0f), rest{}, mie_sum{};
    for (size_t k = begin; k < begin + run; ++k) {
      const Float4 rayleigh_scattering = rayleigh * splat4(steps.rayleigh[k]);
      const Float4 mie_scattering = mie * splat4(steps.mie[k]);
      const Float4 w = throughput * Float4{steps.segment[0][k], steps.segment[1][k], steps.segment[2][k], 0.0f};
      throughput *= Float4{steps.step_t[0][k], steps.step_t[1][k], steps.step_t[2][k], 1.0f};
      add_sample(packed, LutCoord{c.t_y0[k], c.t_y1[k], c.t_wy[k]}, LutCoord{c.ms_y0[k], c.ms_y1[k], c.ms_wy[k]},
                 c.t_x0[k], c.t_x1[k], c.t_w[k], c.visible[k], c.ms_x0[k], c.ms_x1[k], c.ms_w[k],
                 MsView{c.q_xx[k], c.q_yy[k], c.q_xy[k], c.v_x[k], c.v_y[k]}, phase_r,
                 w * rayleigh_scattering, w * mie_scattering, w * (rayleigh_scattering + mie_scattering), rest,
                 mie_sum);
    }
    shaded[r] = {to_vec3(rest), to_vec3(mie_sum)};
    transmittance[r] = to_vec3(throughput);
  }
}

}  // namespace cr

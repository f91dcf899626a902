#include "atmosphere/scattering_march.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/atmosphere_density.h"
#include "atmosphere/float4.h"
#include "atmosphere/march_lookups.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "engine/core/fast_math.h"

namespace cr {

int variable_steps(float length, int min_steps, int max_steps) {
  const float f = std::clamp(length * 1e-5f, 0.0f, 1.0f);
  return std::max(1, int(std::lround(float(min_steps) + f * float(max_steps - min_steps))));
}

void MarchSteps::resize(size_t n) {
  for (auto* v : {&t, &dt, &h, &rayleigh, &mie}) v->resize(n);
  for (int c = 0; c < 3; ++c) {
    step_t[c].resize(n);
    segment[c].resize(n);
  }
}

namespace {

// march_media's loop over its n steps; restrict parameters (not locals: GCC
// honours only these) let it vectorize.
void media_of_steps(const AtmosphereModel& m, float h0, float mu, float floor_altitude, size_t n,
                    const float* __restrict t, const float* __restrict dt, float* __restrict h,
                    float* __restrict rayleigh, float* __restrict mie, float* __restrict t0, float* __restrict t1,
                    float* __restrict t2, float* __restrict s0, float* __restrict s1, float* __restrict s2) {
  const DensityProfile profile(m);
  const float R = float(m.bottom_radius);
  const float h0_term = h0 * (2.0f * R + h0);
  const float r0mu = (R + h0) * mu;
  const glm::vec3 rs = m.rayleigh_scattering, ms = m.mie_scattering, ma = m.mie_absorption, oa = m.ozone_absorption;
  for (size_t k = 0; k < n; ++k) {
    const float a = altitude_along_ray(R, h0_term, r0mu, t[k]);
    h[k] = a > floor_altitude ? a : floor_altitude;
    const Densities d = profile.at(h[k]);
    rayleigh[k] = d.rayleigh;
    mie[k] = d.mie;
    // medium_from()'s extinction, channel by channel, with the same operations
    const float tau0 = ((rs.x * d.rayleigh + ms.x * d.mie) + ma.x * d.mie + oa.x * d.ozone) * dt[k];
    const float tau1 = ((rs.y * d.rayleigh + ms.y * d.mie) + ma.y * d.mie + oa.y * d.ozone) * dt[k];
    const float tau2 = ((rs.z * d.rayleigh + ms.z * d.mie) + ma.z * d.mie + oa.z * d.ozone) * dt[k];
    t0[k] = fast_exp_neg(-tau0);
    t1[k] = fast_exp_neg(-tau1);
    t2[k] = fast_exp_neg(-tau2);
    s0[k] = one_minus_exp_over_x(tau0, t0[k]) * dt[k];
    s1[k] = one_minus_exp_over_x(tau1, t1[k]) * dt[k];
    s2[k] = one_minus_exp_over_x(tau2, t2[k]) * dt[k];
  }
}

}  // namespace

void march_media(const AtmosphereModel& m, float h0, float mu, float floor_altitude, MarchSteps& steps) {
  media_of_steps(m, h0, mu, floor_altitude, steps.t.size(), steps.t.data(), steps.dt.data(), steps.h.data(),
                 steps.rayleigh.data(), steps.mie.data(), steps.step_t[0].data(), steps.step_t[1].data(),
                 steps.step_t[2].data(), steps.segment[0].data(), steps.segment[1].data(), steps.segment[2].data());
}

void accumulate(const AtmosphereLuts& luts, const MarchSteps& steps, size_t begin, size_t end, float h0, float mu,
                MarchedRay& out) {
  const AtmosphereModel& m = luts.model;
  const float R = float(m.bottom_radius);
  const float top = float(m.atmosphere_height());
  const float ms_scale = float(luts.multiscattering.image().height - 1) / top;
  out.r0 = R + h0;
  out.r0_mu = out.r0 * mu;
  out.samples.resize(end - begin);
  glm::vec3 throughput(1.0f);
  for (size_t k = begin; k < end; ++k) {
    const float h = steps.h[k];
    const glm::vec3 rayleigh_scattering = m.rayleigh_scattering * steps.rayleigh[k];
    const glm::vec3 mie_scattering = m.mie_scattering * steps.mie[k];
    MarchSample& s = out.samples[k - begin];
    s.t = steps.t[k];
    s.inv_r = 1.0f / (R + h);
    s.row = luts.transmittance.row(h);
    s.ms_y = std::min(h, top) * ms_scale;
    const glm::vec3 w = throughput * glm::vec3(steps.segment[0][k], steps.segment[1][k], steps.segment[2][k]);
    s.w_rayleigh = w * rayleigh_scattering;
    s.w_mie = w * mie_scattering;
    s.w_ms = w * (rayleigh_scattering + mie_scattering);
    throughput *= glm::vec3(steps.step_t[0][k], steps.step_t[1][k], steps.step_t[2][k]);
  }
  out.transmittance = throughput;
  out.hits_ground = false;
}

void march(const AtmosphereLuts& luts, float h0, float mu, float t_begin, float t_end, int steps,
           StepSpacing spacing, bool ends_on_ground, float floor_altitude, MarchedRay& out) {
  thread_local MarchSteps scratch;
  scratch.resize(size_t(steps));
  const float length = std::max(t_end - t_begin, 0.0f);
  for (int k = 0; k < steps; ++k) {
    float f0 = float(k) / float(steps);
    float f1 = float(k + 1) / float(steps);
    if (spacing == StepSpacing::Quadratic) {  // denser near the start, where the camera's detail is
      f0 *= f0;
      f1 *= f1;
    }
    scratch.dt[size_t(k)] = (f1 - f0) * length;
    scratch.t[size_t(k)] = t_begin + 0.5f * (f0 + f1) * length;
  }
  march_media(luts.model, h0, mu, floor_altitude, scratch);
  accumulate(luts, scratch, 0, size_t(steps), h0, mu, out);
  out.hits_ground = ends_on_ground;
  if (ends_on_ground) {
    out.ground_t = t_end;
    out.ground_row = luts.transmittance.row(0.0f);
    out.ground_ms_y = 0.0f;
  }
}

namespace {

// Lambertian ground at the end of a ray: direct sun plus the sky light
// estimated from Psi_ms (the sphere-mean scattered luminance at the ground,
// so E_sky ~ pi * Psi), seen through the ray's transmittance.
glm::vec3 ground_luminance(const AtmosphereLuts& luts, const MarchedRay& ray, float r0_mu_s, float nu) {
  const float inv_r = 1.0f / float(luts.model.bottom_radius);
  const float mu_g = std::clamp((r0_mu_s + ray.ground_t * nu) * inv_r, -1.0f, 1.0f);
  const glm::vec3 sun = luts.transmittance.sun(ray.ground_row, mu_g) * std::max(mu_g, 0.0f);
  const glm::vec3 psi = luts.multiscattering.sample(0.0f, mu_g);
  return ray.transmittance * luts.model.ground_albedo * (sun / kPi + psi);
}

}  // namespace

glm::vec3 shade(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu) {
  return shade_split(luts, ray, mu_s, nu).total(mie_phase(luts.model, nu));
}

namespace {

// Per-direction intermediates of shade_split_many, one thread's.
struct ShadeScratch {
  std::vector<int> t_x0, t_x1, ms_x0, ms_x1;
  std::vector<float> t_w, sun_visible, ms_w, phase_r, q_xx, q_yy, q_xy, v_x, v_y;
  std::vector<Float4> rest, mie;
  void resize(size_t n) {
    for (auto* v : {&t_x0, &t_x1, &ms_x0, &ms_x1}) v->resize(n);
    for (auto* v : {&t_w, &sun_visible, &ms_w, &phase_r, &q_xx, &q_yy, &q_xy, &v_x, &v_y}) v->resize(n);
    rest.assign(n, Float4{});
    mie.assign(n, Float4{});
  }
};

// sample_coordinate() of one march sample for n directions nu[j]; restrict
// pointers: it vectorizes. Kept out of line: inlined into shade_split_many's
// sample loop, GCC loses the restrict qualifiers and runs it scalar (a 1.4x
// slower sky-view bake).
__attribute__((noinline)) void sample_coordinates(const TransmittanceRow& row, int t_width, int ms_width,
                                                  float r0_mu, float r0_mu_s, float t, float inv_r, size_t n,
                                                  const float* __restrict nu, int* __restrict t_x0,
                                                  int* __restrict t_x1, float* __restrict t_w,
                                                  float* __restrict sun_visible, int* __restrict ms_x0,
                                                  int* __restrict ms_x1, float* __restrict ms_w,
                                                  float* __restrict q_xx, float* __restrict q_yy,
                                                  float* __restrict q_xy, float* __restrict v_x,
                                                  float* __restrict v_y) {
  for (size_t j = 0; j < n; ++j) {
    MsView view;
    sample_coordinate(row, t_width, ms_width, r0_mu, r0_mu_s, t, inv_r, nu[j], t_x0[j], t_x1[j], t_w[j],
                      sun_visible[j], ms_x0[j], ms_x1[j], ms_w[j], view);
    q_xx[j] = view.q_xx;
    q_yy[j] = view.q_yy;
    q_xy[j] = view.q_xy;
    v_x[j] = view.v_x;
    v_y[j] = view.v_y;
  }
}

}  // namespace

ShadedRay shade_split(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu) {
  const float phase_r = rayleigh_phase(nu);
  const LutImage& ms = luts.multiscattering.image();
  const float r0_mu_s = ray.r0 * mu_s;
  const PackedLuts packed(luts.transmittance, luts.multiscattering);
  Float4 rest{}, mie{};
  for (const MarchSample& s : ray.samples) {
    int t_x0, t_x1, ms_x0, ms_x1;
    float t_w, sun_visible, ms_w;
    MsView view;
    sample_coordinate(s.row, luts.transmittance.image().width, ms.width, ray.r0_mu, r0_mu_s, s.t, s.inv_r, nu, t_x0,
                      t_x1, t_w, sun_visible, ms_x0, ms_x1, ms_w, view);
    add_sample(packed, s.row.y, lut_coord(s.ms_y, ms.height), t_x0, t_x1, t_w, sun_visible, ms_x0, ms_x1, ms_w, view,
               phase_r, to_float4(s.w_rayleigh), to_float4(s.w_mie), to_float4(s.w_ms), rest, mie);
  }
  glm::vec3 l = to_vec3(rest);
  if (ray.hits_ground) l += ground_luminance(luts, ray, r0_mu_s, nu);
  return {l, to_vec3(mie)};
}

// The lookup coordinates of all directions at a step come from sample_coordinates (same IEEE results).
void shade_split_many(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, size_t n, const float* nu,
                      ShadedRay* out) {
  thread_local ShadeScratch sc;
  sc.resize(n);
  const LutImage& ms = luts.multiscattering.image();
  const LutImage& tr = luts.transmittance.image();
  const float r0_mu_s = ray.r0 * mu_s;
  const PackedLuts packed(luts.transmittance, luts.multiscattering);
  for (size_t j = 0; j < n; ++j) sc.phase_r[j] = rayleigh_phase(nu[j]);
  for (const MarchSample& s : ray.samples) {
    sample_coordinates(s.row, tr.width, ms.width, ray.r0_mu, r0_mu_s, s.t, s.inv_r, n, nu, sc.t_x0.data(),
                       sc.t_x1.data(), sc.t_w.data(), sc.sun_visible.data(), sc.ms_x0.data(), sc.ms_x1.data(),
                       sc.ms_w.data(), sc.q_xx.data(), sc.q_yy.data(), sc.q_xy.data(), sc.v_x.data(), sc.v_y.data());
    const LutCoord ms_y = lut_coord(s.ms_y, ms.height);
    const Float4 w_rayleigh = to_float4(s.w_rayleigh), w_mie = to_float4(s.w_mie), w_ms = to_float4(s.w_ms);
    for (size_t j = 0; j < n; ++j)
      add_sample(packed, s.row.y, ms_y, sc.t_x0[j], sc.t_x1[j], sc.t_w[j], sc.sun_visible[j], sc.ms_x0[j], sc.ms_x1[j],
                 sc.ms_w[j], MsView{sc.q_xx[j], sc.q_yy[j], sc.q_xy[j], sc.v_x[j], sc.v_y[j]}, sc.phase_r[j], w_rayleigh, w_mie, w_ms, sc.rest[j], sc.mie[j]);
  }
  for (size_t j = 0; j < n; ++j) {
    glm::vec3 l = to_vec3(sc.rest[j]);
    if (ray.hits_ground) l += ground_luminance(luts, ray, r0_mu_s, nu[j]);
    out[j] = {l, to_vec3(sc.mie[j])};
  }
}

RayScattering integrate_ray(const AtmosphereLuts& luts, double r, double mu, double mu_s, double nu,
                            double max_distance, int min_steps, int max_steps, MarchedRay& scratch) {
  const AtmosphereModel& m = luts.model;
  RayScattering result;
  r = std::max(r, m.bottom_radius);
  double offset = 0.0;
  if (r > m.top_radius) {  // from space: start where the ray enters the atmosphere
    const double b = r * mu;
    const double disc = b * b - (r * r - m.top_radius * m.top_radius);
    if (disc < 0.0 || mu >= 0.0) return result;
    offset = -b - std::sqrt(disc);
    const double r_entry = m.top_radius;
    mu = std::clamp((r * mu + offset) / r_entry, -1.0, 1.0);
    mu_s = std::clamp((r * mu_s + offset * nu) / r_entry, -1.0, 1.0);
    r = r_entry;
  }
  const double t_ground = distance_to_ground(r, mu, m.bottom_radius);
  const double t_top = std::max(distance_to_sphere_exit(r, mu, m.top_radius), 0.0);
  double t_end = t_ground >= 0.0 ? t_ground : t_top;
  bool ground = t_ground >= 0.0;
  if (max_distance - offset < t_end) {
    t_end = std::max(max_distance - offset, 0.0);
    ground = false;
  }
  result.hits_ground = ground;
  if (t_end <= 0.0) return result;
  const int steps = variable_steps(float(t_end), min_steps, max_steps);
  const float h0 = float(r - m.bottom_radius);
  march(luts, h0, float(mu), 0.0f, float(t_end), steps, StepSpacing::Quadratic, ground, 0.0f, scratch);
  result.luminance = shade(luts, scratch, float(mu_s), float(nu));
  result.transmittance = scratch.transmittance;
  return result;
}

}  // namespace cr

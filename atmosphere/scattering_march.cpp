#include "atmosphere/scattering_march.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/atmosphere_density.h"
#include "atmosphere/fast_math.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"

namespace cr {

int variable_steps(float length, int min_steps, int max_steps) {
  const float f = std::clamp(length * 1e-5f, 0.0f, 1.0f);
  return std::max(1, int(std::lround(float(min_steps) + f * float(max_steps - min_steps))));
}

void march(const AtmosphereLuts& luts, float h0, float mu, float t_begin, float t_end, int steps,
           StepSpacing spacing, bool ends_on_ground, float floor_altitude, MarchedRay& out) {
  const AtmosphereModel& m = luts.model;
  const DensityProfile profile(m);
  const float R = float(m.bottom_radius);
  const float h0_term = h0 * (2.0f * R + h0);
  const float r0 = R + h0;
  const float r0mu = r0 * mu;
  const float top = float(m.atmosphere_height());
  const float ms_scale = float(luts.multiscattering.image().height - 1) / top;
  out.r0 = r0;
  out.samples.resize(size_t(steps));
  glm::vec3 throughput(1.0f);
  const float length = std::max(t_end - t_begin, 0.0f);
  for (int k = 0; k < steps; ++k) {
    float f0 = float(k) / float(steps);
    float f1 = float(k + 1) / float(steps);
    if (spacing == StepSpacing::Quadratic) {  // denser near the start, where the camera's detail is
      f0 *= f0;
      f1 *= f1;
    }
    const float dt = (f1 - f0) * length;
    const float t = t_begin + 0.5f * (f0 + f1) * length;
    const float h = std::max(altitude_along_ray(R, h0_term, r0mu, t), floor_altitude);
    const MediumSample med = medium_from(m, profile.at(h));
    glm::vec3 seg, step_t;
    for (int c = 0; c < 3; ++c) {
      const float tau = med.extinction[c] * dt;
      step_t[c] = fast_exp_neg(-tau);
      seg[c] = one_minus_exp_over_x(tau, step_t[c]) * dt;
    }
    MarchSample& s = out.samples[size_t(k)];
    s.t = t;
    s.inv_r = 1.0f / (R + h);
    s.row = luts.transmittance.row(h);
    s.ms_y = std::min(h, top) * ms_scale;
    const glm::vec3 w = throughput * seg;
    s.w_rayleigh = w * med.rayleigh_scattering;
    s.w_mie = w * med.mie_scattering;
    s.w_ms = w * med.scattering;
    throughput *= step_t;
  }
  out.transmittance = throughput;
  out.hits_ground = ends_on_ground;
  if (ends_on_ground) {
    out.ground_t = t_end;
    out.ground_row = luts.transmittance.row(0.0f);
    out.ground_ms_y = 0.0f;
  }
}

glm::vec3 shade(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu) {
  return shade_split(luts, ray, mu_s, nu).total(mie_phase(luts.model, nu));
}

ShadedRay shade_split(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu) {
  const float phase_r = rayleigh_phase(nu);
  const LutImage& ms = luts.multiscattering.image();
  const float ms_x_scale = 0.5f * float(ms.width - 1);
  const float r0_mu_s = ray.r0 * mu_s;
  glm::vec3 l(0.0f), mie(0.0f);
  for (const MarchSample& s : ray.samples) {
    const float mu_s_t = std::clamp((r0_mu_s + s.t * nu) * s.inv_r, -1.0f, 1.0f);
    const glm::vec3 sun = luts.transmittance.sun(s.row, mu_s_t);
    const glm::vec3 psi = sample_bilinear(ms, (mu_s_t + 1.0f) * ms_x_scale, s.ms_y);
    l += sun * s.w_rayleigh * phase_r + psi * s.w_ms;
    mie += sun * s.w_mie;
  }
  if (ray.hits_ground) {
    // Lambertian ground: direct sun plus the sky light estimated from Psi_ms
    // (the sphere-mean scattered luminance at the ground, so E_sky ~ pi * Psi).
    const float inv_r = 1.0f / float(luts.model.bottom_radius);
    const float mu_g = std::clamp((r0_mu_s + ray.ground_t * nu) * inv_r, -1.0f, 1.0f);
    const glm::vec3 sun = luts.transmittance.sun(ray.ground_row, mu_g) * std::max(mu_g, 0.0f);
    const glm::vec3 psi = sample_bilinear(ms, (mu_g + 1.0f) * ms_x_scale, 0.0f);
    l += ray.transmittance * luts.model.ground_albedo * (sun / kPi + psi);
  }
  return {l, mie};
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

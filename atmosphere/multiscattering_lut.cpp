#include "atmosphere/multiscattering_lut.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "atmosphere/atmosphere_density.h"
#include "atmosphere/float4.h"
#include "engine/core/q15_scale.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/spectral_mix.h"
#include "engine/core/fast_math.h"
#include "engine/core/math_constants.h"

namespace cr {

// One marched step of one direction: everything that does not depend on the sun.
struct MarchStep {
  float tx_over_r;  // horizontal offset / r at the sample (sun-plane component)
  float y_over_r;   // vertical position / r at the sample
  glm::vec3 rayleigh_weight;  // throughput * Rayleigh scattering * (1 - T_step) / extinction
  glm::vec3 mie_weight;       // the same with Mie scattering
  TransmittanceRow row;
};

// Directions and steps of one altitude, shared by all sun angles of a row.
struct AltitudeMarch {
  std::vector<MarchStep> steps;       // directions x steps
  std::vector<glm::vec3> fms;         // per direction, sum of weights
  std::vector<glm::vec3> ground_tp;   // per direction: throughput at the ground * albedo / pi (0: no hit)
  std::vector<float> ground_x, ground_y;  // ground hit point / R
  std::vector<TransmittanceRow> ground_row;
  std::vector<float> dir_weight;
  std::vector<float> dir_x, dir_y;  // direction components in the sun plane (x: towards the sun, y: up)
  // The steps' sun-lookup inputs again, one array each, for a loop that vectorizes.
  std::vector<float> tx_over_r, y_over_r, row_r, row_d_min, row_inv_d_range, row_top2_minus_r2, row_mu_horizon,
      row_penumbra;
  std::vector<Float4> rayleigh_weight, mie_weight;  // the steps' weights as rgb + pad
  // For the explicit orders (MultiScatteringLut::add_field_rows): the steps'
  // altitude coordinates in the LUT, the same for every sun angle of the row,
  // and their total scattering weight (isotropic re-scattering).
  std::vector<LutCoord> field_y;
  std::vector<Float4> scatter_weight;
};

namespace {

// The polar angles of the directions: n bands uniform in u in [-1, 1], mapped
// to cos = mu_h +- (1 -+ mu_h) u^2 about the local horizon mu_h, so the bands
// are thin where the luminance and the optical depth change fastest (rays
// just above the horizon are hundreds of km long, those just below end on the
// ground nearby). `weight` is the band's share of the sphere (its cos range / 2).
struct PolarBand {
  double cos_p;
  double weight;
};

PolarBand polar_band(int b, int n, double mu_horizon) {
  const double u = 1.0 - 2.0 * (double(b) + 0.5) / double(n);
  const double side = u >= 0.0 ? 1.0 - mu_horizon : 1.0 + mu_horizon;  // cos range on this side of the horizon
  return {mu_horizon + (u >= 0.0 ? side : -side) * u * u, side * std::abs(u) * 2.0 / double(n)};
}

// Irradiance of the ground from a unit isotropic in-scattered field (every
// point of the medium scattering sigma_s * 1 towards it): the ground's share
// of f_ms. Marched over the upper hemisphere with the same bands and steps.
glm::vec3 ground_irradiance_per_unit_field(const AtmosphereModel& m, int bands, int steps) {
  const DensityProfile profile(m);
  const double R = m.bottom_radius;
  glm::vec3 e(0.0f);
  for (int b = 0; b < bands / 2; ++b) {  // the upper half of the bands: above the ground's horizon (mu_h = 0)
    const PolarBand band = polar_band(b, bands, 0.0);
    const double t_max = std::max(distance_to_sphere_exit(R, band.cos_p, m.top_radius), 0.0);
    const float dt = float(t_max / steps);
    glm::vec3 throughput(1.0f), l(0.0f);
    for (int k = 0; k < steps; ++k) {
      const float t = (float(k) + 0.5f) * dt;
      const MediumSample med = medium_from(m, profile.at(altitude_along_ray(float(R), 0.0f, float(R * band.cos_p), t)));
      for (int c = 0; c < 3; ++c) {
        const float tau = med.extinction[c] * dt;
        const float step_t = fast_exp_neg(-tau);
        l[c] += throughput[c] * med.scattering[c] * one_minus_exp_over_x(tau, step_t) * dt;
        throughput[c] *= step_t;
      }
    }
    e += l * float(4.0 * kPiD * band.weight * band.cos_p);  // solid angle (the band's sphere share * 4 pi) * cos
  }
  return e;
}

// lut: null when only the medium's terms are wanted (no sun lookups follow).
AltitudeMarch march_altitude(const AtmosphereModel& m, const TransmittanceLut* lut, float altitude,
                             int directions, int steps, const glm::vec3& ground_irradiance) {
  const int n = int(std::lround(std::sqrt(double(directions))));
  const int half = n / 2;  // mirror symmetry about the sun plane: half the azimuths, weight 2
  const double R = m.bottom_radius;
  const DensityProfile profile(m);
  const double r0 = R + double(altitude);
  const double mu_horizon = -std::sqrt(std::max(0.0, 1.0 - (R / r0) * (R / r0)));
  const float h0_term = altitude * (2.0f * float(R) + altitude);
  AltitudeMarch am;
  const int dir_count = n * half;
  am.steps.resize(size_t(dir_count) * steps);
  am.fms.assign(size_t(dir_count), glm::vec3(0.0f));
  am.ground_tp.assign(size_t(dir_count), glm::vec3(0.0f));
  am.ground_x.assign(size_t(dir_count), 0.0f);
  am.ground_y.assign(size_t(dir_count), 0.0f);
  am.ground_row.assign(size_t(dir_count), lut ? lut->row(0.0f) : TransmittanceRow{});
  am.dir_weight.assign(size_t(dir_count), 0.0f);
  am.dir_x.assign(size_t(dir_count), 0.0f);
  am.dir_y.assign(size_t(dir_count), 0.0f);
  for (int a = 0; a < half; ++a) {
    const double azimuth = 2.0 * kPiD * (double(a) + 0.5) / n;
    for (int b = 0; b < n; ++b) {
      const int d = a * n + b;
      const PolarBand band = polar_band(b, n, mu_horizon);
      const double cos_p = band.cos_p;
      am.dir_weight[size_t(d)] = float(band.weight / double(half));
      const double sin_p = std::sqrt(std::max(0.0, 1.0 - cos_p * cos_p));
      const double dir_x = sin_p * std::cos(azimuth);  // in the sun plane (sun has z = 0)
      const double dir_y = cos_p;
      am.dir_x[size_t(d)] = float(dir_x);
      am.dir_y[size_t(d)] = float(dir_y);
      const double t_ground = distance_to_ground(r0, cos_p, R);
      const double t_max = t_ground >= 0.0 ? t_ground : std::max(distance_to_sphere_exit(r0, cos_p, m.top_radius), 0.0);
      const float dt = float(t_max / steps);
      glm::vec3 throughput(1.0f);
      for (int k = 0; k < steps; ++k) {
        const float t = (float(k) + 0.5f) * dt;
        const float h = altitude_along_ray(float(R), h0_term, float(r0 * cos_p), t);
        const float r = float(R) + h;
        const MediumSample med = medium_from(m, profile.at(h));
        glm::vec3 seg, step_t;
        for (int c = 0; c < 3; ++c) {
          const float tau = med.extinction[c] * dt;
          step_t[c] = fast_exp_neg(-tau);
          seg[c] = one_minus_exp_over_x(tau, step_t[c]) * dt;
        }
        MarchStep& s = am.steps[size_t(d) * steps + k];
        s.tx_over_r = float(double(t) * dir_x) / r;
        s.y_over_r = float(r0 + double(t) * dir_y) / r;
        s.rayleigh_weight = throughput * med.rayleigh_scattering * seg;
        s.mie_weight = throughput * med.mie_scattering * seg;
        s.row = lut ? lut->row(h) : TransmittanceRow{};
        am.fms[size_t(d)] += throughput * med.scattering * seg;
        throughput *= step_t;
      }
      if (t_ground >= 0.0) {
        am.ground_tp[size_t(d)] = throughput * m.ground_albedo / kPi;
        // The ground lit by the isotropic field reflects it back: part of the transfer.
        am.fms[size_t(d)] += am.ground_tp[size_t(d)] * ground_irradiance;
        am.ground_x[size_t(d)] = float(t_ground * dir_x / R);
        am.ground_y[size_t(d)] = float((r0 + t_ground * dir_y) / R);
      }
    }
  }
  for (auto* v : {&am.tx_over_r, &am.y_over_r, &am.row_r, &am.row_d_min, &am.row_inv_d_range,
                  &am.row_top2_minus_r2, &am.row_mu_horizon, &am.row_penumbra})
    v->resize(am.steps.size());
  am.rayleigh_weight.resize(am.steps.size());
  am.mie_weight.resize(am.steps.size());
  for (size_t k = 0; k < am.steps.size(); ++k) {
    const MarchStep& s = am.steps[k];
    am.rayleigh_weight[k] = to_float4(s.rayleigh_weight);
    am.mie_weight[k] = to_float4(s.mie_weight);
    am.tx_over_r[k] = s.tx_over_r;
    am.y_over_r[k] = s.y_over_r;
    am.row_r[k] = s.row.r;
    am.row_d_min[k] = s.row.d_min;
    am.row_inv_d_range[k] = s.row.inv_d_range;
    am.row_top2_minus_r2[k] = s.row.top2_minus_r2;
    am.row_mu_horizon[k] = s.row.mu_horizon;
    am.row_penumbra[k] = s.row.penumbra;
  }
  return am;
}

// The sun transmittance lookups of every step of every direction for one sun
// angle (sin_s, mu_s): one loop that vectorizes. Out of line: inlined into
// integrate_sun, GCC loses the restrict qualifiers and runs it scalar.
__attribute__((noinline)) void sun_lookups(size_t n, int width, float sin_s, float mu_s, const float* __restrict tx_over_r,
                 const float* __restrict y_over_r, const float* __restrict r, const float* __restrict d_min,
                 const float* __restrict inv_d_range, const float* __restrict top2_minus_r2,
                 const float* __restrict mu_horizon, const float* __restrict penumbra, int* __restrict x0,
                 int* __restrict x1, float* __restrict w, float* __restrict visible) {
  for (size_t k = 0; k < n; ++k) {
    const float mu = tx_over_r[k] * sin_s + y_over_r[k] * mu_s;
    TransmittanceRow row{};
    row.r = r[k];
    row.d_min = d_min[k];
    row.inv_d_range = inv_d_range[k];
    row.top2_minus_r2 = top2_minus_r2[k];
    row.mu_horizon = mu_horizon[k];
    row.penumbra = penumbra[k];
    sun_lookup(row, width, mu, x0[k], x1[k], w[k], visible[k]);
  }
}

// The LUT column coordinates of every step's sun angle for one sun angle
// (sin_s, mu_s), as sample_field() computes them: one loop that vectorizes.
__attribute__((noinline)) void field_columns(size_t n, int width, float sin_s, float mu_s,
                                             const float* __restrict tx_over_r, const float* __restrict y_over_r,
                                             int* __restrict x0, int* __restrict x1, float* __restrict wx) {
  for (size_t k = 0; k < n; ++k) {
    // std::min / std::max, not nested selects: with to_unit's select GCC's if-conversion gives up.
    const float mu = std::max(-1.0f, std::min(1.0f, tx_over_r[k] * sin_s + y_over_r[k] * mu_s));
    const float u = std::max(0.0f, std::min(1.0f, MultiScatteringMapping::to_unit(mu)));
    const float x = u * float(width - 1);
    const int i0 = int(x) < width - 1 ? int(x) : width - 1;
    x0[k] = i0;
    x1[k] = i0 + 1 < width - 1 ? i0 + 1 : width - 1;
    wx[k] = x - float(i0);
  }
}

// What integrate_sun gives for one texel: the second-order luminance's
// sphere mean l2 and its moments, and the transfer factor f_ms.
struct SecondOrder {
  glm::vec3 l2{0.0f};
  std::array<glm::vec3, kMsMomentCount> moments{};
  glm::vec3 fms{0.0f};
  glm::vec3 sky_irradiance{0.0f};  // of a horizontal surface at the point, from the upper hemisphere
};

SecondOrder integrate_sun(const AtmosphereModel& m, const AltitudeMarch& am, const TransmittanceLut& lut, int steps,
                          float mu_s) {
  const float sin_s = std::sqrt(std::max(0.0f, 1.0f - mu_s * mu_s));
  SecondOrder out;
  const size_t dirs = am.fms.size();
  const size_t n = am.steps.size();
  thread_local std::vector<int> x0, x1;
  thread_local std::vector<float> w, visible;
  x0.resize(n);
  x1.resize(n);
  w.resize(n);
  visible.resize(n);
  const int width = lut.image().width;
  sun_lookups(n, width, sin_s, mu_s, am.tx_over_r.data(), am.y_over_r.data(), am.row_r.data(), am.row_d_min.data(),
              am.row_inv_d_range.data(), am.row_top2_minus_r2.data(), am.row_mu_horizon.data(),
              am.row_penumbra.data(), x0.data(), x1.data(), w.data(), visible.data());
  const float* texels = lut.packed();
  // The sun's light scatters into each direction with the true phase of its
  // scattering angle (Hillaire uses the isotropic one): in twilight the lit
  // air sits on one side and what reaches the shadowed air is mostly
  // scattered forwards. Each phase is normalised over the directions, so
  // the quadrature keeps the scattered energy whatever its resolution.
  thread_local std::vector<float> phase_r, phase_m;
  phase_r.resize(dirs);
  phase_m.resize(dirs);
  float sum_r = 0.0f, sum_m = 0.0f;
  for (size_t d = 0; d < dirs; ++d) {
    const float cos_theta = am.dir_x[d] * sin_s + am.dir_y[d] * mu_s;  // the direction towards the sun's
    phase_r[d] = rayleigh_phase(cos_theta);
    phase_m[d] = mie_phase(m, cos_theta);
    sum_r += phase_r[d] * am.dir_weight[d];
    sum_m += phase_m[d] * am.dir_weight[d];
  }
  // sum_x is the directions' mean phase; the normalised one averages 1 / (4 pi).
  const float norm_r = kIsotropicPhase / sum_r, norm_m = kIsotropicPhase / sum_m;
  for (size_t d = 0; d < dirs; ++d) {
    Float4 rayleigh{}, mie{};
    for (size_t k = d * size_t(steps); k < (d + 1) * size_t(steps); ++k) {
      const TransmittanceRow& row = am.steps[k].row;
      // weight * lut.sun(row, mu), as rgb + pad texels
      const Float4 sun = bilinear4(texels, width, x0[k], x1[k], w[k], row.y.i0, row.y.i1, row.y.w) * splat4(visible[k]);
      rayleigh += am.rayleigh_weight[k] * sun;
      mie += am.mie_weight[k] * sun;
    }
    glm::vec3 l = to_vec3(rayleigh) * (phase_r[d] * norm_r) + to_vec3(mie) * (phase_m[d] * norm_m);
    if (am.ground_tp[d] != glm::vec3(0.0f)) {
      const float mu_g = am.ground_x[d] * sin_s + am.ground_y[d] * mu_s;
      l += am.ground_tp[d] * lut.sun(am.ground_row[d], mu_g) * std::max(mu_g, 0.0f);
    }
    // L2 and f_ms are sphere integrals of isotropically re-scattered light: means over directions.
    const glm::vec3 lw = l * am.dir_weight[d];
    out.l2 += lw;
    out.fms += am.fms[d] * am.dir_weight[d];
    const float x = am.dir_x[d], y = am.dir_y[d];
    out.moments[kMsQuadXX] += lw * (3.0f * x * x - 1.0f);
    out.moments[kMsQuadYY] += lw * (3.0f * y * y - 1.0f);
    out.moments[kMsQuadXY] += lw * (3.0f * x * y);
    out.moments[kMsFirstX] += lw * x;
    out.moments[kMsFirstY] += lw * y;
    if (y > 0.0f) out.sky_irradiance += lw * (4.0f * kPi * y);
  }
  return out;
}

}  // namespace

ExplicitOrderChoice explicit_orders_for(const AtmosphereModel& model, int height, int directions, int steps,
                                        float max_fms, int min_orders, int max_orders, float tail_share) {
  const int bands = int(std::lround(std::sqrt(double(directions))));
  const glm::vec3 ground_irradiance = ground_irradiance_per_unit_field(model, bands, steps);
  ExplicitOrderChoice c;
  for (int y = 0; y < height; ++y) {
    // The bake's row altitude and sum (bake(), integrate_sun()).
    const float altitude = float(y) / float(height - 1) * float(model.atmosphere_height());
    const AltitudeMarch am = march_altitude(model, nullptr, altitude, directions, steps, ground_irradiance);
    glm::vec3 f(0.0f);
    for (size_t d = 0; d < am.fms.size(); ++d) f += am.fms[d] * am.dir_weight[d];
    c.max_fms = std::max(c.max_fms, std::max(f.x, std::max(f.y, f.z)));
  }
  const float fc = std::min(c.max_fms, max_fms);
  c.orders = min_orders;
  float share = std::pow(fc, float(min_orders + 1));
  while (c.orders < max_orders && share > tail_share) {
    ++c.orders;
    share *= fc;
  }
  c.capped = share > tail_share;
  return c;
}

MultiScatteringLut::MultiScatteringLut(const AtmosphereModel& model, int width, int height, int directions, int steps,
                                       float max_fms, int explicit_orders)
    : model_(model),
      directions_(directions),
      steps_(steps),
      max_fms_(max_fms),
      explicit_orders_(explicit_orders),
      inv_top_altitude_(float(1.0 / model.atmosphere_height())),
      image_(width, height),
      packed_(4 * image_.count(), 0.0f),
      moments_(size_t(kMsMomentCount) * 4 * image_.count(), 0.0f),
      clamped_(image_.count(), 0),
      fms_(image_.count(), 0.0f),
      fields_(size_t(std::max(explicit_orders, 1) + 1), std::vector<float>(4 * image_.count(), 0.0f)),
      transfer_(image_.count()),
      ground_sky_(size_t(image_.width)),
      ground_irradiance_(ground_irradiance_per_unit_field(
          model, int(std::lround(std::sqrt(double(directions)))), steps)) {
  moment_images_.fill(LutImage(width, height));
  const std::array<double, 2> k = mie_legendre_coefficients(model);
  moment_scale_ = {0.25f, 0.25f, 0.25f, float(3.0 * k[0]), float(3.0 * k[0])};
  mie_quadratic_ratio_ = float(10.0 * k[1]);
}

void MultiScatteringLut::bake(size_t begin, size_t end, const TransmittanceLut& transmittance) {
  const size_t count = image_.count();
  const int w = image_.width;
  size_t item = begin;
  while (item < end) {
    const int pass = int(item / count);
    const size_t i0 = item % count;
    const int y = int(i0 / size_t(w));
    const size_t row_end = std::min(end, size_t(pass) * count + size_t(y + 1) * size_t(w));
    const float altitude = float(y) / float(image_.height - 1) * float(model_.atmosphere_height());
    AltitudeMarch am = march_altitude(model_, &transmittance, altitude, directions_, steps_, ground_irradiance_);
    if (pass > 0) add_field_rows(am);
    for (; item < row_end; ++item) {
      const size_t i = item % count;
      const float mu_s = MultiScatteringMapping::from_unit(float(i % size_t(w)) / float(w - 1));
      if (pass == 0)
        bake_second_order(am, transmittance, i, mu_s, y == 0);
      else
        bake_higher_order(am, pass, i, mu_s);
    }
  }
}

void MultiScatteringLut::bake_second_order(const AltitudeMarch& am, const TransmittanceLut& transmittance, size_t i,
                                           float mu_s, bool ground_row) {
  const SecondOrder so = integrate_sun(model_, am, transmittance, steps_, mu_s);
  const float fmax = std::max(so.fms.x, std::max(so.fms.y, so.fms.z));
  clamped_[i] = fmax > max_fms_ ? 1 : 0;
  fms_[i] = fmax;
  transfer_[i] = glm::min(so.fms, glm::vec3(max_fms_));
  std::memcpy(&fields_[0][4 * i], &so.l2, sizeof so.l2);
  if (ground_row) ground_sky_[i] = so.sky_irradiance;
  for (int k = 0; k < kMsMomentCount; ++k) {
    const glm::vec3 v = so.moments[size_t(k)] * moment_scale_[size_t(k)];
    moment_images_[size_t(k)].texels[i] = v;
    std::memcpy(&moments_[(size_t(k) * image_.count() + i) * 4], &v, sizeof v);
  }
}

glm::vec3 MultiScatteringLut::ground_sky(float mu) const {
  const int w = image_.width;
  const float x = std::clamp(MultiScatteringMapping::to_unit(mu), 0.0f, 1.0f) * float(w - 1);
  const int x0 = std::min(int(x), w - 2);
  const float f = x - float(x0);
  return ground_sky_[size_t(x0)] * (1.0f - f) + ground_sky_[size_t(x0) + 1] * f;
}

void MultiScatteringLut::bake_higher_order(const AltitudeMarch& am, int pass, size_t i, float mu_s) {
  const glm::vec3 l2 = to_vec3(load4(&fields_[0][4 * i]));
  const glm::vec3 f = transfer_[i];
  glm::vec3 field(0.0f);
  if (pass <= explicit_orders_)
    field = march_field(am, fields_[size_t(pass) - 1].data(), mu_s);
  else
    field = l2 * f;  // no explicit order: Hillaire's estimate of the third
  if (pass == 1) field += ground_skylight(am, mu_s);
  std::memcpy(&fields_[size_t(pass)][4 * i], &field, sizeof field);
  if (pass + 1 < passes()) return;
  // The explicit orders, then the series for the tail from the last one.
  glm::vec3 psi = field / (glm::vec3(1.0f) - f);
  for (int q = 0; q < pass; ++q) psi += to_vec3(load4(&fields_[size_t(q)][4 * i]));
  image_.texels[i] = psi;
  std::memcpy(&packed_[4 * i], &psi, sizeof psi);
}

// The next order's field at a texel: each step scatters the previous order's
// field (at its own altitude and sun angle; isotropic), the ground reflects
// the light the medium scatters onto it (as in f_ms).
glm::vec3 MultiScatteringLut::march_field(const AltitudeMarch& am, const float* previous, float mu_s) const {
  const float sin_s = std::sqrt(std::max(0.0f, 1.0f - mu_s * mu_s));
  const size_t n = am.steps.size();
  thread_local std::vector<int> x0, x1;
  thread_local std::vector<float> wx;
  x0.resize(n);
  x1.resize(n);
  wx.resize(n);
  const int w = image_.width;
  field_columns(n, w, sin_s, mu_s, am.tx_over_r.data(), am.y_over_r.data(), x0.data(), x1.data(), wx.data());
  glm::vec3 sum(0.0f);
  const size_t dirs = am.fms.size();
  for (size_t d = 0; d < dirs; ++d) {
    Float4 l{};
    for (size_t k = d * size_t(steps_); k < (d + 1) * size_t(steps_); ++k) {
      const LutCoord& y = am.field_y[k];
      l += am.scatter_weight[k] * bilinear4(previous, w, x0[k], x1[k], wx[k], y.i0, y.i1, y.w);
    }
    glm::vec3 ld = to_vec3(l);
    if (am.ground_tp[d] != glm::vec3(0.0f)) {
      const float mu_g = std::clamp(am.ground_x[d] * sin_s + am.ground_y[d] * mu_s, -1.0f, 1.0f);
      ld += am.ground_tp[d] * ground_irradiance_ * to_vec3(sample_field(previous, 0.0f, mu_g));
    }
    sum += ld * am.dir_weight[d];
  }
  return sum;
}

void MultiScatteringLut::add_field_rows(AltitudeMarch& am) const {
  const size_t n = am.steps.size();
  const float bottom = float(model_.bottom_radius);
  am.field_y.resize(n);
  am.scatter_weight.resize(n);
  for (size_t k = 0; k < n; ++k) {
    am.field_y[k] = field_row(am.row_r[k] - bottom);
    am.scatter_weight[k] = am.rayleigh_weight[k] + am.mie_weight[k];
  }
}

LutCoord MultiScatteringLut::field_row(float altitude) const {
  const int h = image_.height;
  return lut_coord(std::clamp(altitude, 0.0f, 1.0f / inv_top_altitude_) * (float(h - 1) * inv_top_altitude_), h);
}

// The ground lit by the once-scattered sky (the second-order field's upper
// hemisphere at the ground) reflecting it towards the texel: light scattered
// twice, so part of the third order. Hillaire's f_ms has the ground reflect
// only what the medium scatters onto it, which leaves this term out; it is
// about a tenth of the multiple scattering near the ground under a high sun.
glm::vec3 MultiScatteringLut::ground_skylight(const AltitudeMarch& am, float mu_s) const {
  const float sin_s = std::sqrt(std::max(0.0f, 1.0f - mu_s * mu_s));
  glm::vec3 sum(0.0f);
  for (size_t d = 0; d < am.fms.size(); ++d) {
    if (am.ground_tp[d] == glm::vec3(0.0f)) continue;
    const float mu_g = std::clamp(am.ground_x[d] * sin_s + am.ground_y[d] * mu_s, -1.0f, 1.0f);
    sum += am.ground_tp[d] * ground_sky(mu_g) * am.dir_weight[d];
  }
  return sum;
}

Float4 MultiScatteringLut::sample_field(const float* field, float altitude, float mu) const {
  const int w = image_.width;
  const float x = std::clamp(MultiScatteringMapping::to_unit(mu), 0.0f, 1.0f) * float(w - 1);
  const int x0 = std::min(int(x), w - 1), x1 = std::min(x0 + 1, w - 1);
  const LutCoord yc = field_row(altitude);
  return bilinear4(field, w, x0, x1, x - float(x0), yc.i0, yc.i1, yc.w);
}

glm::vec3 MultiScatteringLut::second_order(float altitude, float mu_s) const {
  return to_vec3(sample_field(fields_[0].data(), altitude, mu_s));
}

int MultiScatteringLut::clamped_texels() const {
  int n = 0;
  for (uint8_t c : clamped_) n += c;
  return n;
}

float MultiScatteringLut::max_fms_seen() const {
  float m = 0.0f;
  for (float f : fms_) m = std::max(m, f);
  return m;
}

void MultiScatteringLut::mix_from(const std::vector<const MultiScatteringLut*>& groups,
                                  const SpectralSampling& sampling, JobSystem& jobs) {
  const size_t n = image_.count();
  mix_image(image_.texels.data(), n, groups, sampling, jobs,
            [](const MultiScatteringLut& l) -> const LutImage& { return l.image_; },
            0.0f);
  for (size_t i = 0; i < n; ++i) std::memcpy(&packed_[4 * i], &image_.texels[i], sizeof(glm::vec3));
  for (size_t k = 0; k < moment_images_.size(); ++k) {
    mix_image(moment_images_[k].texels.data(), n, groups, sampling, jobs,
              [k](const MultiScatteringLut& l) -> const LutImage& { return l.moment_images_[k]; });
    for (size_t i = 0; i < n; ++i)
      std::memcpy(&moments_[(k * n + i) * 4], &moment_images_[k].texels[i], sizeof(glm::vec3));
  }
  for (const MultiScatteringLut* g : groups)
    for (size_t i = 0; i < n; ++i) {
      clamped_[i] = std::max(clamped_[i], g->clamped_[i]);
      fms_[i] = std::max(fms_[i], g->fms_[i]);
    }
}

void MultiScatteringLut::quantize_q15() {
  const Q15Scale s = q15_scale_for(max_value(&image_.texels[0].x, 3 * image_.count(), 1));
  round_to_q15(&image_.texels[0].x, 3 * image_.count(), 1, s);
  for (int c = 0; c < 3; ++c) round_to_q15(packed_.data() + c, image_.count(), 4, s);
}

}  // namespace cr

#include "atmosphere/transmittance_lut.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "atmosphere/atmosphere_density.h"
#include "atmosphere/float4.h"
#include "engine/core/q15_scale.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/spectral_mix.h"

namespace cr {

TransmittanceMapping::TransmittanceMapping(const AtmosphereModel& m)
    : ground_radius(float(m.bottom_radius)),
      top_altitude(float(m.atmosphere_height())),
      horizon_top(float(std::sqrt(m.atmosphere_height() * (2.0 * m.bottom_radius + m.atmosphere_height())))) {}

glm::vec2 TransmittanceMapping::to_unit(float altitude, float mu) const {
  const float h = std::clamp(altitude, 0.0f, top_altitude);
  const float r = ground_radius + h;
  const float rho = std::sqrt(h * (2.0f * ground_radius + h));
  const float top2_minus_r2 = (top_altitude - h) * (2.0f * ground_radius + top_altitude + h);
  const float mu_c = std::clamp(mu, -1.0f, 1.0f);
  const float d = std::max(0.0f, -r * mu_c + std::sqrt(std::max(r * r * mu_c * mu_c + top2_minus_r2, 0.0f)));
  const float d_min = top_altitude - h;
  const float d_max = rho + horizon_top;
  const float x_mu = d_max > d_min ? (d - d_min) / (d_max - d_min) : 0.0f;
  return {std::clamp(x_mu, 0.0f, 1.0f), rho / horizon_top};
}

void TransmittanceMapping::from_unit(glm::vec2 unit, float& altitude, float& mu) const {
  const double R = ground_radius;
  const double H = horizon_top;
  const double rho = H * double(unit.y);
  const double r = std::sqrt(rho * rho + R * R);
  const double h = rho * rho / (R + r);
  const double d_min = double(top_altitude) - h;
  const double d_max = rho + H;
  const double d = d_min + double(unit.x) * (d_max - d_min);
  const double m = d <= 0.0 ? 1.0 : (H * H - rho * rho - d * d) / (2.0 * r * d);
  altitude = float(h);
  mu = float(std::clamp(m, -1.0, 1.0));
}

// The density loop vectorizes (same IEEE results).
glm::vec3 optical_depth(const AtmosphereModel& m, float h0, float mu, float length, int steps) {
  const float R = float(m.bottom_radius);
  const float h0_term = h0 * (2.0f * R + h0);
  const float r0mu = (R + h0) * mu;
  const float dt = length / float(steps);
  const DensityProfile profile(m);
  // The coefficients are constant along the ray: integrate the three densities
  // only. Densities go to a buffer first (a loop without reductions vectorizes);
  // the sums then run in index order.
  constexpr int kBlock = 64;
  float rayleigh[kBlock], mie[kBlock], ozone[kBlock];
  float sum_rayleigh = 0.0f, sum_mie = 0.0f, sum_ozone = 0.0f;
  for (int k0 = 0; k0 < steps; k0 += kBlock) {
    const int n = std::min(kBlock, steps - k0);
    for (int j = 0; j < n; ++j) {
      const float t = (float(k0 + j) + 0.5f) * dt;
      const Densities d = profile.at(altitude_along_ray(R, h0_term, r0mu, t));
      rayleigh[j] = d.rayleigh;
      mie[j] = d.mie;
      ozone[j] = d.ozone;
    }
    for (int j = 0; j < n; ++j) {
      sum_rayleigh += rayleigh[j];
      sum_mie += mie[j];
      sum_ozone += ozone[j];
    }
  }
  return (m.rayleigh_scattering * sum_rayleigh + (m.mie_scattering + m.mie_absorption) * sum_mie +
          m.ozone_absorption * sum_ozone) * dt;
}

namespace {

// row() and sun_lookup() of n points: selects, restrict pointers and no call,
// so it vectorizes; out of line so that GCC keeps the restricts.
__attribute__((noinline)) void sun_coordinates(const TransmittanceLut& lut, size_t n,
                                               const float* __restrict altitude, const float* __restrict mu_s,
                                               int* __restrict x0, int* __restrict x1, float* __restrict wx,
                                               int* __restrict y0, int* __restrict y1, float* __restrict wy,
                                               float* __restrict visible) {
  const int width = lut.image().width;
  for (size_t i = 0; i < n; ++i) {
    const TransmittanceRow row = lut.row(altitude[i]);
    y0[i] = row.y.i0;
    y1[i] = row.y.i1;
    wy[i] = row.y.w;
    sun_lookup(row, width, mu_s[i], x0[i], x1[i], wx[i], visible[i]);
  }
}

}  // namespace

void TransmittanceLut::sun_batch(const float* altitude, const float* mu_s, size_t n, glm::vec3* out) const {
  constexpr size_t kChunk = 64;
  int x0[kChunk], x1[kChunk], y0[kChunk], y1[kChunk];
  float wx[kChunk], wy[kChunk], visible[kChunk];
  for (size_t begin = 0; begin < n; begin += kChunk) {
    const size_t count = std::min(kChunk, n - begin);
    sun_coordinates(*this, count, altitude + begin, mu_s + begin, x0, x1, wx, y0, y1, wy, visible);
    for (size_t i = 0; i < count; ++i)
      out[begin + i] =
          to_vec3(bilinear4(packed_.data(), image_.width, x0[i], x1[i], wx[i], y0[i], y1[i], wy[i]) * splat4(visible[i]));
  }
}

TransmittanceLut::TransmittanceLut(const AtmosphereModel& model, int width, int height, int steps)
    : model_(model),
      mapping_(model),
      steps_(steps),
      sin_sun_radius_(std::sin(model.sun_angular_radius)),
      image_(width, height),
      packed_(4 * image_.count(), 0.0f) {}

void TransmittanceLut::bake(size_t begin, size_t end) {
  for (size_t i = begin; i < end; ++i) {
    const int x = int(i % size_t(image_.width));
    const int y = int(i / size_t(image_.width));
    const glm::vec2 unit(float(x) / float(image_.width - 1), float(y) / float(image_.height - 1));
    float h, mu;
    mapping_.from_unit(unit, h, mu);
    const double r = model_.bottom_radius + h;
    const double length = std::max(distance_to_sphere_exit(r, mu, model_.top_radius), 0.0);
    const glm::vec3 t = glm::exp(-optical_depth(model_, h, mu, float(length), steps_));
    image_.texels[i] = t;
    std::memcpy(&packed_[4 * i], &t, sizeof t);
  }
}

void TransmittanceLut::mix_from(const std::vector<const TransmittanceLut*>& groups, const SpectralSampling& sampling,
                                JobSystem& jobs) {
  mix_image(image_.texels.data(), image_.count(), groups, sampling, jobs,
            [](const TransmittanceLut& l) -> const LutImage& { return l.image_; },
            0.0f, 1.0f);
  for (size_t i = 0; i < image_.count(); ++i) std::memcpy(&packed_[4 * i], &image_.texels[i], sizeof(glm::vec3));
}

void TransmittanceLut::quantize_q15() {
  const Q15Scale unit;
  round_to_q15(&image_.texels[0].x, 3 * image_.count(), 1, unit);
  for (int c = 0; c < 3; ++c) round_to_q15(packed_.data() + c, image_.count(), 4, unit);
}

}  // namespace cr

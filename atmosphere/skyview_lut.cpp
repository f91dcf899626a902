#include "atmosphere/skyview_lut.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/planet_geometry.h"
#include "atmosphere/q15_texels.h"
#include "atmosphere/spectral_mix.h"
#include "engine/core/fast_math.h"
#include "engine/core/fixed_point.h"
#include "engine/core/math_constants.h"

namespace cr {

SkyViewMapping::SkyViewMapping(double ground_radius, double top_radius, double altitude) {
  const double h = std::max(altitude, 0.0);
  const double to_horizon = std::sqrt(h * (2.0 * ground_radius + h));
  const double b = std::atan2(ground_radius, to_horizon);  // precise even a metre above the ground
  beta = float(b);
  zenith_horizon_angle = float(kPiD - b);
  const double r = ground_radius + h;
  first_angle = r > top_radius ? float(kPiD - std::asin(top_radius / r)) : 0.0f;
}

void SkyViewMapping::from_unit(glm::vec2 unit, double& cos_view_zenith, double& cos_longitude) const {
  double angle;
  if (unit.y < 0.5f) {
    const double c = 1.0 - 2.0 * double(unit.y);
    angle = double(first_angle) + double(zenith_horizon_angle - first_angle) * (1.0 - c * c);
  } else {
    const double c = 2.0 * double(unit.y) - 1.0;
    angle = double(zenith_horizon_angle) + double(beta) * c * c;
  }
  cos_view_zenith = std::cos(angle);
  cos_longitude = 1.0 - 2.0 * double(unit.x) * double(unit.x);
}

SkyViewLut::SkyViewLut(int width, int height, int min_steps, int max_steps, float altitude, float mu_s,
                       double ground_radius, double top_radius)
    : min_steps_(min_steps),
      max_steps_(max_steps),
      altitude_(altitude),
      mu_s_(mu_s),
      mapping_(ground_radius, top_radius, altitude),
      image_(width, height),
      mie_(width, height),
      packed_(size_t(width) * height, SkyViewTexel{}) {}

void SkyViewLut::bake(size_t begin, size_t end, const AtmosphereLuts& luts) {
  const AtmosphereModel& m = luts.model;
  const int w = image_.width;
  const double r = m.bottom_radius + double(altitude_);
  const double sin_s = std::sqrt(std::max(0.0, 1.0 - double(mu_s_) * mu_s_));
  MarchedRay ray;
  std::vector<float> nu;
  std::vector<ShadedRay> shaded;
  size_t i = begin;
  while (i < end) {
    const int y = int(i / size_t(w));
    const size_t row_end = std::min(end, size_t(y + 1) * size_t(w));
    double cos_vz, unused;
    mapping_.from_unit(glm::vec2(0.0f, float(y) / float(image_.height - 1)), cos_vz, unused);
    const double sin_vz = std::sqrt(std::max(0.0, 1.0 - cos_vz * cos_vz));
    // The row's ray is the same for every longitude: march it once. From
    // space it starts where it enters the atmosphere (the tangent row has none).
    const double t_ground = distance_to_ground(r, cos_vz, m.bottom_radius);
    const double t_exit = std::max(distance_to_sphere_exit(r, cos_vz, m.top_radius), 0.0);
    const double t_begin = r > m.top_radius ? std::max(-r * cos_vz - std::sqrt(std::max(
                                                             r * r * (cos_vz * cos_vz - 1.0) + m.top_radius * m.top_radius, 0.0)), 0.0)
                                            : 0.0;
    // Row 0 from space is the tangent to the top: no atmosphere along it (exactly, not up to rounding).
    const bool tangent = r > m.top_radius && y == 0;
    const double t_end = tangent ? t_begin : (t_ground >= 0.0 ? t_ground : std::max(t_exit, t_begin));
    const int steps = variable_steps(float(t_end - t_begin), min_steps_, max_steps_);
    march(luts, altitude_, float(cos_vz), float(t_begin), float(t_end), steps, StepSpacing::Quadratic,
          t_ground >= 0.0, 0.0f, ray);
    // Every longitude of the row shades that ray at once.
    const size_t row_begin = i;
    nu.resize(row_end - row_begin);
    shaded.resize(row_end - row_begin);
    for (size_t k = row_begin; k < row_end; ++k) {
      const int x = int(k % size_t(w));
      double unused_vz, cos_lon;
      mapping_.from_unit(glm::vec2(float(x) / float(w - 1), 0.0f), unused_vz, cos_lon);
      nu[k - row_begin] = float(std::clamp(sin_vz * cos_lon * sin_s + cos_vz * double(mu_s_), -1.0, 1.0));
    }
    shade_split_many(luts, ray, mu_s_, nu.size(), nu.data(), shaded.data());
    for (; i < row_end; ++i) {
      const ShadedRay& sh = shaded[i - row_begin];
      image_.texels[i] = sh.rest;
      mie_.texels[i] = sh.mie_unphased;
      packed_[i] = {{sh.rest.x, sh.rest.y, sh.rest.z, 0.0f},
                    {sh.mie_unphased.x, sh.mie_unphased.y, sh.mie_unphased.z, 0.0f}};
    }
  }
}

void SkyViewLut::mix_from(const std::vector<const SkyViewLut*>& groups, const SpectralSampling& sampling,
                          JobSystem& jobs) {
  mix_image(image_.texels.data(), image_.count(), groups, sampling, jobs,
            [](const SkyViewLut& l) -> const LutImage& { return l.image_; },
            0.0f);
  mix_image(mie_.texels.data(), mie_.count(), groups, sampling, jobs,
            [](const SkyViewLut& l) -> const LutImage& { return l.mie_; },
            0.0f);
  for (size_t i = 0; i < image_.count(); ++i) {
    const glm::vec3 r = image_.texels[i], m = mie_.texels[i];
    packed_[i] = {{r.x, r.y, r.z, 0.0f}, {m.x, m.y, m.z, 0.0f}};
  }
}

void SkyViewLut::quantize_q15() {
  float* rest = &image_.texels[0].x;
  float* mie = &mie_.texels[0].x;
  const size_t n = 3 * image_.count();
  rest_scale_ = q15_scale_for(max_value(rest, n, 1));
  mie_scale_ = q15_scale_for(max_value(mie, n, 1));
  round_to_q15(rest, n, 1, rest_scale_);
  round_to_q15(mie, n, 1, mie_scale_);
  packed_q15_.resize(image_.count());
  for (size_t i = 0; i < image_.count(); ++i) {
    const glm::vec3 r = image_.texels[i], m = mie_.texels[i];
    packed_[i] = {{r.x, r.y, r.z, 0.0f}, {m.x, m.y, m.z, 0.0f}};
    packed_q15_[i] = {{to_q15(r.x, rest_scale_), to_q15(r.y, rest_scale_), to_q15(r.z, rest_scale_), 0},
                      {to_q15(m.x, mie_scale_), to_q15(m.y, mie_scale_), to_q15(m.z, mie_scale_), 0}};
  }
}

glm::vec3 SkyViewLut::sample_fixed(glm::vec2 unit, float mie_phase_value) const {
  const LutCoord x = lut_coord(unit.x * float(image_.width - 1), image_.width);
  const LutCoord y = lut_coord(unit.y * float(image_.height - 1), image_.height);
  const SkyViewTexelQ15* row0 = &packed_q15_[size_t(y.i0) * size_t(image_.width)];
  const SkyViewTexelQ15* row1 = &packed_q15_[size_t(y.i1) * size_t(image_.width)];
  const fx::U16x8 v = bilinear_q15(&row0[x.i0], &row0[x.i1], &row1[x.i0], &row1[x.i1],
                                   splat_weight(fx::weight_q15(x.w)), splat_weight(fx::weight_q15(y.w)));
  Float4 rest, mie;
  decode_halves(v, rest_scale_.scale, mie_scale_.scale, rest, mie);
  return to_vec3(rest + mie * splat4(mie_phase_value));
}

}  // namespace cr

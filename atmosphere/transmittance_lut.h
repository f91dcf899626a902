#pragma once
// LUT 1: transmittance from a point to the top of the atmosphere, over
// (altitude, view zenith cosine) with Bruneton's mapping: x_r = rho/H (rho the
// distance to the horizon), x_mu = (d - d_min)/(d_max - d_min) (d the distance
// to the top). Only rays that miss the ground are stored; the sun lookup adds
// the planet's shadow with a penumbra over the sun disk.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/lut_image.h"
#include "atmosphere/spectral_sampling.h"

namespace cr {

class JobSystem;

// The (altitude, mu) <-> unit square mapping of one planet.
struct TransmittanceMapping {
  float ground_radius = 0.0f;
  float top_altitude = 0.0f;  // top radius - ground radius
  float horizon_top = 0.0f;   // H = sqrt(top^2 - R^2)

  explicit TransmittanceMapping(const AtmosphereModel& m = AtmosphereModel());
  glm::vec2 to_unit(float altitude, float mu) const;              // (x_mu, x_r)
  void from_unit(glm::vec2 unit, float& altitude, float& mu) const;
};

// Per-altitude constants of a lookup, shared by every mu at that altitude.
struct TransmittanceRow {
  float r;
  float d_min;
  float inv_d_range;
  float top2_minus_r2;
  float mu_horizon;
  float penumbra;  // sin(sun radius) * cos(horizon): half width of the shadow transition in mu
  LutCoord y;
};

class TransmittanceLut {
 public:
  TransmittanceLut() = default;
  TransmittanceLut(const AtmosphereModel& model, int width, int height, int steps);

  // Computes texels [begin, end) (row-major); disjoint ranges may run in parallel.
  void bake(size_t begin, size_t end);
  size_t texel_count() const { return image_.count(); }

  TransmittanceRow row(float altitude) const;
  // Transmittance to the top along mu (clamped to the horizon: rays into the ground read the horizon).
  glm::vec3 to_top(const TransmittanceRow& row, float mu) const;
  // Sunlight transmittance at the row's altitude for sun zenith cosine mu_s,
  // zero in the planet's shadow, smooth over the sun disk's size.
  glm::vec3 sun(const TransmittanceRow& row, float mu_s) const;
  glm::vec3 sun(float altitude, float mu_s) const { return sun(row(altitude), mu_s); }
  // sun(altitude[i], mu_s[i]) into out[i] for n points, bit for bit: the rows
  // and texel coordinates of many points come from one loop that vectorizes.
  void sun_batch(const float* altitude, const float* mu_s, size_t n, glm::vec3* out) const;

  // Rounds the image to q15 (scale 1: T = 1 is 1 - 2^-15; T under 2^-16
  // becomes 0); for "luts": "q15".
  void quantize_q15();
  // The image from the LUTs of a spectral sampling's groups (spectral_mix.h),
  // same size and mapping, clipped to [0, 1]; this LUT's model is the RGB one.
  void mix_from(const std::vector<const TransmittanceLut*>& groups, const SpectralSampling& sampling, JobSystem& jobs);

  const LutImage& image() const { return image_; }
  const float* packed() const { return packed_.data(); }  // the image as rgb + pad (see float4.h)
  const AtmosphereModel& model() const { return model_; }
  const TransmittanceMapping& mapping() const { return mapping_; }

 private:
  AtmosphereModel model_;
  TransmittanceMapping mapping_;
  int steps_ = 40;
  float sin_sun_radius_ = 0.0f;
  LutImage image_;
  std::vector<float> packed_;
};

// Optical depth along a ray from altitude h0 with zenith cosine mu over
// distance `length`, by `steps` midpoint samples (shared with the tests).
glm::vec3 optical_depth(const AtmosphereModel& m, float h0, float mu, float length, int steps);

// sun() up to the texel fetch, branch-free for vector loops: the LUT columns
// x0, x1 and weight w (the row's y coordinate completes the bilinear sample)
// and the visible fraction of the sun disk (0 in the planet's shadow; the
// sample times it is sun()'s result, bit for bit). `width`: the LUT's.
inline void sun_lookup(const TransmittanceRow& row, int width, float mu_s, int& x0, int& x1, float& w,
                       float& visible) {
  const float above = mu_s - row.mu_horizon;
  const float s = (above + row.penumbra) / (2.0f * row.penumbra);
  visible = above <= -row.penumbra ? 0.0f : (above >= row.penumbra ? 1.0f : s * s * (3.0f - 2.0f * s));
  // to_top() and lut_coord(), with selects for std::clamp / std::min / std::max
  const float mu = mu_s < row.mu_horizon ? row.mu_horizon : (1.0f < mu_s ? 1.0f : mu_s);
  const float disc = row.r * row.r * mu * mu + row.top2_minus_r2;
  const float d = -row.r * mu + std::sqrt(disc < 0.0f ? 0.0f : disc);
  const float last = float(width - 1);
  float x = (d - row.d_min) * row.inv_d_range * last;
  x = x > 0.0f ? (x < last ? x : last) : 0.0f;
  x0 = int(x) < width - 1 ? int(x) : width - 1;
  x1 = x0 + 1 < width - 1 ? x0 + 1 : width - 1;
  w = x - float(x0);
}

inline TransmittanceRow TransmittanceLut::row(float altitude) const {
  const float R = mapping_.ground_radius;
  // Selects, not std::clamp: inlined into the batched lookups' loops, it vectorizes.
  const float h = altitude < 0.0f ? 0.0f : (mapping_.top_altitude < altitude ? mapping_.top_altitude : altitude);
  TransmittanceRow row;
  row.r = R + h;
  const float rho = std::sqrt(h * (2.0f * R + h));
  row.d_min = mapping_.top_altitude - h;
  const float d_range = rho + mapping_.horizon_top - row.d_min;
  row.inv_d_range = d_range > 0.0f ? 1.0f / d_range : 0.0f;
  row.top2_minus_r2 = (mapping_.top_altitude - h) * (2.0f * R + mapping_.top_altitude + h);
  row.mu_horizon = -rho / row.r;
  row.penumbra = sin_sun_radius_ * (R / row.r);
  row.y = lut_coord(rho / mapping_.horizon_top * float(image_.height - 1), image_.height);
  return row;
}

inline glm::vec3 TransmittanceLut::to_top(const TransmittanceRow& row, float mu) const {
  mu = std::clamp(mu, row.mu_horizon, 1.0f);
  const float d = -row.r * mu + std::sqrt(std::max(row.r * row.r * mu * mu + row.top2_minus_r2, 0.0f));
  const float x_mu = (d - row.d_min) * row.inv_d_range;
  return sample_bilinear(image_, lut_coord(x_mu * float(image_.width - 1), image_.width), row.y);
}

inline glm::vec3 TransmittanceLut::sun(const TransmittanceRow& row, float mu_s) const {
  const float above = mu_s - row.mu_horizon;
  if (above <= -row.penumbra) return glm::vec3(0.0f);
  const glm::vec3 t = to_top(row, mu_s);
  if (above >= row.penumbra) return t;
  const float s = (above + row.penumbra) / (2.0f * row.penumbra);  // visible fraction of the disk
  return t * (s * s * (3.0f - 2.0f * s));
}

}  // namespace cr

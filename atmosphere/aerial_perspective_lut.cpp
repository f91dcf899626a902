#include "atmosphere/aerial_perspective_lut.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "atmosphere/froxel_column.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/spectral_mix.h"

namespace cr {

glm::vec3 FroxelCamera::column_direction(float px, float py, int w, int h) const {
  const float sx = (2.0f * px / float(w) - 1.0f) * tan_half_fov * aspect;
  const float sy = (1.0f - 2.0f * py / float(h)) * tan_half_fov;
  return glm::normalize(forward + sx * right + sy * up);
}

AerialPerspectiveLut::AerialPerspectiveLut(int width, int height, int depth, float km_per_slice,
                                           int steps_per_slice, const FroxelCamera& camera)
    : km_per_slice_(km_per_slice),
      steps_per_slice_(steps_per_slice),
      camera_(camera),
      luminance_(width, height, depth),
      transmittance_(width, height, depth),
      packed_(size_t(width + 1) * size_t(height + 1) * size_t(depth), FroxelTexel{}) {}

float AerialPerspectiveLut::slice_distance(int slice) const {
  const float depth = float(luminance_.depth);
  const float f = (float(slice) + 0.5f) / depth;
  return f * f * depth * km_per_slice_ * 1000.0f;
}

float AerialPerspectiveLut::slice_coordinate(float distance) const {
  return std::sqrt(std::max(distance, 0.0f) / extent()) * float(luminance_.depth) - 0.5f;
}

void AerialPerspectiveLut::bake(size_t begin, size_t end, const AtmosphereLuts& luts) {
  const AtmosphereModel& m = luts.model;
  const double r0 = glm::length(camera_.position);
  const glm::dvec3 up0 = camera_.position / r0;
  const float h0 = float(r0 - m.bottom_radius);
  // Samples below the ground are pushed 10 m above it (never above the camera itself).
  const float floor_altitude = std::clamp(h0, 0.0f, 10.0f);
  const float mu_s = float(glm::dot(glm::dvec3(camera_.sun_direction), up0));
  const int w = luminance_.width;
  const int depth = luminance_.depth;
  const size_t steps = size_t(depth) * size_t(steps_per_slice_);
  // The steps of a column: uniform within each slice, as march() spaces them.
  MarchSteps column;
  column.resize(steps);
  float t_begin = 0.0f;
  for (int s = 0; s < depth; ++s) {
    const float t_end = slice_distance(s);
    const float length = std::max(t_end - t_begin, 0.0f);
    for (int k = 0; k < steps_per_slice_; ++k) {
      const float f0 = float(k) / float(steps_per_slice_), f1 = float(k + 1) / float(steps_per_slice_);
      const size_t i = size_t(s) * size_t(steps_per_slice_) + size_t(k);
      column.dt[i] = (f1 - f0) * length;
      column.t[i] = t_begin + 0.5f * (f0 + f1) * length;
    }
    t_begin = t_end;
  }
  const float h_start = std::max(h0, 0.0f);
  std::vector<ShadedRay> shaded(static_cast<size_t>(depth));
  std::vector<glm::vec3> slice_transmittance(static_cast<size_t>(depth));
  for (size_t c = begin; c < end; ++c) {
    const int x = int(c % size_t(w));
    const int y = int(c / size_t(w));
    const glm::vec3 dir = camera_.column_direction(float(x) + 0.5f, float(y) + 0.5f, w, luminance_.height);
    const float mu = float(glm::dot(glm::dvec3(dir), up0));
    const float nu = std::clamp(glm::dot(dir, camera_.sun_direction), -1.0f, 1.0f);
    const float mie_phase_value = mie_phase(m, nu);  // constant along the column
    // The whole column's medium and each slice's scattering at once, then the slices front to back.
    march_media(m, h_start, mu, floor_altitude, column);
    shade_runs(luts, column, h_start, mu, mu_s, nu, size_t(steps_per_slice_), shaded.data(), slice_transmittance.data());
    glm::vec3 l(0.0f), t(1.0f);
    for (int s = 0; s < depth; ++s) {
      l += t * shaded[size_t(s)].total(mie_phase_value);
      t *= slice_transmittance[size_t(s)];
      luminance_.at(x, y, s) = l;
      transmittance_.at(x, y, s) = t;
      const FroxelTexel texel = {{l.x, l.y, l.z, 0.0f}, {t.x, t.y, t.z, 0.0f}};
      // The column's own texel and its copies in the padding (written by this column's job only).
      for (int py = y; py <= (y + 1 == luminance_.height ? y + 1 : y); ++py)
        for (int px = x; px <= (x + 1 == w ? x + 1 : x); ++px) packed_[packed_index(px, py, s)] = texel;
    }
  }
}

void AerialPerspectiveLut::mix_from(const std::vector<const AerialPerspectiveLut*>& groups,
                                    const SpectralSampling& sampling, JobSystem& jobs) {
  const size_t n = luminance_.count();
  mix_image(luminance_.texels.data(), n, groups, sampling, jobs,
            [](const AerialPerspectiveLut& l) -> const LutImage& { return l.luminance_; }, 0.0f);
  mix_image(transmittance_.texels.data(), n, groups, sampling, jobs,
            [](const AerialPerspectiveLut& l) -> const LutImage& { return l.transmittance_; }, 0.0f, 1.0f);
  repack();
}

void AerialPerspectiveLut::repack() {
  const int w = luminance_.width, h = luminance_.height;
  for (int z = 0; z < luminance_.depth; ++z)
    for (int py = 0; py <= h; ++py)
      for (int px = 0; px <= w; ++px) {
        const glm::vec3 lv = luminance_.at(std::min(px, w - 1), std::min(py, h - 1), z);
        const glm::vec3 tv = transmittance_.at(std::min(px, w - 1), std::min(py, h - 1), z);
        packed_[packed_index(px, py, z)] = {{lv.x, lv.y, lv.z, 0.0f}, {tv.x, tv.y, tv.z, 0.0f}};
      }
}

void AerialPerspectiveLut::quantize_q15() {
  float* l = &luminance_.texels[0].x;
  float* t = &transmittance_.texels[0].x;
  const size_t n = 3 * luminance_.count();
  luminance_scale_ = q15_scale_for(max_value(l, n, 1));
  const Q15Scale unit;
  round_to_q15(l, n, 1, luminance_scale_);
  round_to_q15(t, n, 1, unit);
  repack();
  packed_q15_.resize(packed_.size());
  for (size_t i = 0; i < packed_.size(); ++i) {
    const float* lv = packed_[i].luminance;
    const float* tv = packed_[i].transmittance;
    packed_q15_[i] = {{to_q15(lv[0], luminance_scale_), to_q15(lv[1], luminance_scale_), to_q15(lv[2], luminance_scale_), 0},
                      {to_q15(tv[0], unit), to_q15(tv[1], unit), to_q15(tv[2], unit), 0}};
  }
}

}  // namespace cr

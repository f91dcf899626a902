#include "atmosphere/aerial_perspective_lut.h"

#include <algorithm>
#include <cmath>

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
      packed_(size_t(width) * height * depth, FroxelTexel{}) {}

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
  MarchedRay ray;
  for (size_t c = begin; c < end; ++c) {
    const int x = int(c % size_t(w));
    const int y = int(c / size_t(w));
    const glm::vec3 dir = camera_.column_direction(float(x) + 0.5f, float(y) + 0.5f, w, luminance_.height);
    const float mu = float(glm::dot(glm::dvec3(dir), up0));
    const float nu = std::clamp(glm::dot(dir, camera_.sun_direction), -1.0f, 1.0f);
    glm::vec3 l(0.0f), t(1.0f);
    float t_begin = 0.0f;
    for (int s = 0; s < luminance_.depth; ++s) {
      const float t_end = slice_distance(s);
      march(luts, std::max(h0, 0.0f), mu, t_begin, t_end, steps_per_slice_, StepSpacing::Uniform, false,
            floor_altitude, ray);
      l += t * shade(luts, ray, mu_s, nu);
      t *= ray.transmittance;
      luminance_.at(x, y, s) = l;
      transmittance_.at(x, y, s) = t;
      packed_[luminance_.index(x, y, s)] = {{l.x, l.y, l.z, 0.0f}, {t.x, t.y, t.z, 0.0f}};
      t_begin = t_end;
    }
  }
}

}  // namespace cr

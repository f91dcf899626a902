#pragma once
// LUT 4: aerial perspective froxels over the camera frustum: width x height
// columns through pixel-aligned directions, depth slices at squared distances
// t_s = ((s + 0.5)/depth)^2 * depth * km_per_slice. Each froxel stores the
// in-scattered luminance (unit sun illuminance) and the transmittance from the
// camera to its slice. A column is marched once, front to back, accumulating
// slice by slice; samples under the ground are pushed 10 m above it.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/lut_image.h"
#include "engine/core/q15_scale.h"
#include "atmosphere/scattering_march.h"

namespace cr {

class JobSystem;

// The camera a froxel volume was built for, in planet-centred coordinates.
struct FroxelCamera {
  glm::dvec3 position{0.0};  // relative to the planet centre
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  glm::vec3 right{1.0f, 0.0f, 0.0f};
  float tan_half_fov = 0.57735f;
  float aspect = 1.0f;
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};
  // Direction of froxel column (x, y) of a w x h grid (same rule as Camera::ray_direction).
  glm::vec3 column_direction(float px, float py, int w, int h) const;
};

// A froxel laid out for the composite: luminance and transmittance in one 32-byte block.
struct FroxelTexel {
  float luminance[4];      // rgb, pad
  float transmittance[4];  // rgb, pad
};

// The same froxel quantised (engine/core/q15_scale.h): 8 codes, one 16-byte vector.
struct FroxelTexelQ15 {
  uint16_t luminance[4];      // rgb, pad (0); the LUT's luminance scale
  uint16_t transmittance[4];  // rgb, pad (0); scale 1
};

class AerialPerspectiveLut {
 public:
  AerialPerspectiveLut() = default;
  AerialPerspectiveLut(int width, int height, int depth, float km_per_slice, int steps_per_slice,
                       const FroxelCamera& camera);

  void bake(size_t begin, size_t end, const AtmosphereLuts& luts);  // columns [begin, end) (x fastest)
  size_t column_count() const { return size_t(luminance_.width) * luminance_.height; }

  float slice_distance(int slice) const;        // metres from the camera to slice `slice`
  float slice_coordinate(float distance) const;  // inverse: fractional slice index (may be < 0 or > depth-1)
  float range() const { return slice_distance(luminance_.depth - 1); }
  float extent() const { return float(luminance_.depth) * km_per_slice_ * 1000.0f; }  // depth * km_per_slice

  const LutImage& luminance() const { return luminance_; }
  const LutImage& transmittance() const { return transmittance_; }
  // Both images interleaved, (width + 1) x (height + 1) x depth: the extra
  // column and row repeat the last ones, so a bilinear footprint starting at
  // any texel stays inside without a clamp.
  const std::vector<FroxelTexel>& packed() const { return packed_; }
  size_t packed_index(int x, int y, int z) const {
    return (size_t(z) * size_t(luminance_.height + 1) + size_t(y)) * size_t(luminance_.width + 1) + size_t(x);
  }
  const FroxelCamera& camera() const { return camera_; }

  // Rounds both images to q15 (luminance with one scale, transmittance with
  // scale 1) and fills packed_q15() in packed()'s layout; for "luts": "q15".
  void quantize_q15();
  // Both images from the LUTs of a spectral sampling's groups (spectral_mix.h),
  // built with the same arguments; luminance clipped at 0, transmittance to [0, 1].
  void mix_from(const std::vector<const AerialPerspectiveLut*>& groups, const SpectralSampling& sampling,
                JobSystem& jobs);
  bool quantized() const { return !packed_q15_.empty(); }
  const std::vector<FroxelTexelQ15>& packed_q15() const { return packed_q15_; }
  const Q15Scale& luminance_scale() const { return luminance_scale_; }

 private:
  void repack();  // packed() from the two images

  float km_per_slice_ = 4.0f;
  int steps_per_slice_ = 2;
  FroxelCamera camera_;
  LutImage luminance_;
  LutImage transmittance_;
  std::vector<FroxelTexel> packed_;
  std::vector<FroxelTexelQ15> packed_q15_;
  Q15Scale luminance_scale_;
};

}  // namespace cr

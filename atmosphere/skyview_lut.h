#pragma once
// LUT 3: the sky seen from the camera, over (longitude relative to the sun,
// view zenith), single + multiple scattering for unit sun illuminance. Valid
// for one camera altitude and sun zenith angle; the sun's azimuth only turns
// it. Hillaire's non-linear latitude mapping puts the horizon between the two
// middle rows and squeezes texels towards it on both sides; the longitude
// mapping u = sqrt((1 - cos)/2) concentrates texels towards the sun. The Mie
// single scattering is stored without its phase, which is applied per pixel.
// Above the atmosphere (camera in space) the same parameterisation holds with
// the rows spanning only the directions that meet the atmosphere: from the
// tangent to its top down to the nadir, the planet's limb between the middle
// rows; the sky there is one LUT lookup instead of a per-pixel ray march.
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/lut_image.h"
#include "engine/core/q15_scale.h"
#include "atmosphere/scattering_march.h"
#include "engine/core/fast_math.h"

namespace cr {

class JobSystem;

struct SkyViewMapping {
  float zenith_horizon_angle = 0.0f;  // zenith angle of the horizon (> pi/2 above the ground)
  float beta = 0.0f;                  // angle between the horizon and the nadir
  float first_angle = 0.0f;           // zenith angle of row 0: 0 inside the atmosphere, its tangent from space

  SkyViewMapping() = default;
  SkyViewMapping(double ground_radius, double top_radius, double altitude);
  // (cos view zenith, cos longitude from the sun) -> unit square
  glm::vec2 to_unit(float cos_view_zenith, float cos_longitude) const;
  void from_unit(glm::vec2 unit, double& cos_view_zenith, double& cos_longitude) const;
};

// A texel laid out for the composite: both parts of one texel in one 32-byte block.
struct SkyViewTexel {
  float rest[4];          // rgb, pad
  float mie_unphased[4];  // rgb, pad
};

// The same texel quantised (engine/core/q15_scale.h): 8 codes, one 16-byte vector.
struct SkyViewTexelQ15 {
  uint16_t rest[4];          // rgb, pad (0)
  uint16_t mie_unphased[4];  // rgb, pad (0)
};

// Selects for the branches, std::clamp and std::min (same results, NaN included):
// inlined into a loop over many directions, it vectorizes.
inline glm::vec2 SkyViewMapping::to_unit(float cos_view_zenith, float cos_longitude) const {
  const float angle = fast_acos(cos_view_zenith);
  const float above = 1.0f - (angle - first_angle) / (zenith_horizon_angle - first_angle);
  const float below = (angle - zenith_horizon_angle) / beta;
  const float v = angle < zenith_horizon_angle
                      ? 0.5f * (1.0f - std::sqrt(above < 0.0f ? 0.0f : (1.0f < above ? 1.0f : above)))
                      : 0.5f + 0.5f * std::sqrt(below < 1.0f ? below : 1.0f);
  const float uu = 0.5f - 0.5f * cos_longitude;
  return {std::sqrt(uu < 0.0f ? 0.0f : (1.0f < uu ? 1.0f : uu)), v};
}

class SkyViewLut {
 public:
  SkyViewLut() = default;
  // The LUT for a camera at `altitude` (above the top: seen from space) with the sun at zenith cosine `mu_s`.
  SkyViewLut(int width, int height, int min_steps, int max_steps, float altitude, float mu_s, double ground_radius,
             double top_radius);

  void bake(size_t begin, size_t end, const AtmosphereLuts& luts);  // texels [begin, end), row-major
  size_t texel_count() const { return image_.count(); }

  // Luminance for unit sun illuminance along a direction with these LUT
  // coordinates; mie_phase_value = the Mie phase of that direction (applied per
  // pixel, not stored: a LUT texel is far wider than the forward lobe).
  glm::vec3 sample(glm::vec2 unit, float mie_phase_value) const {
    const LutCoord x = lut_coord(unit.x * float(image_.width - 1), image_.width);
    const LutCoord y = lut_coord(unit.y * float(image_.height - 1), image_.height);
    return sample_bilinear(image_, x, y) + sample_bilinear(mie_, x, y) * mie_phase_value;
  }
  // Rounds both images to q15 (one scale each) and fills packed_q15(); for "luts": "q15".
  void quantize_q15();
  // Both images from the LUTs of a spectral sampling's groups (spectral_mix.h),
  // built with the same arguments; clipped at 0.
  void mix_from(const std::vector<const SkyViewLut*>& groups, const SpectralSampling& sampling, JobSystem& jobs);
  bool quantized() const { return !packed_q15_.empty(); }
  // sample() from the q15 texels in 16-bit integer arithmetic: both parts
  // lerped as 8 codes (u, then v: fx::lerp_q15 with q15 weights), then
  // decoded, the Mie part times its phase. The composite's fixed kernel
  // computes exactly this. Needs quantize_q15().
  glm::vec3 sample_fixed(glm::vec2 unit, float mie_phase_value) const;
  const std::vector<SkyViewTexelQ15>& packed_q15() const { return packed_q15_; }
  const Q15Scale& rest_scale() const { return rest_scale_; }
  const Q15Scale& mie_scale() const { return mie_scale_; }
  const SkyViewMapping& mapping() const { return mapping_; }
  float altitude() const { return altitude_; }
  float mu_s() const { return mu_s_; }
  const LutImage& image() const { return image_; }      // all but Mie single scattering
  const LutImage& mie_image() const { return mie_; }    // Mie single scattering without phase
  const std::vector<SkyViewTexel>& packed() const { return packed_; }  // both images interleaved

 private:
  int min_steps_ = 4;
  int max_steps_ = 14;
  float altitude_ = 0.0f;
  float mu_s_ = 1.0f;
  SkyViewMapping mapping_;
  LutImage image_;
  LutImage mie_;
  std::vector<SkyViewTexel> packed_;
  std::vector<SkyViewTexelQ15> packed_q15_;
  Q15Scale rest_scale_, mie_scale_;
};

}  // namespace cr

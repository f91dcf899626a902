#pragma once
// LUT 2: Hillaire's multiple-scattering term Psi_ms over (sun zenith cosine,
// altitude). Per texel, `directions` rays are marched (sqrt(directions) polar
// bands, denser near the local horizon; isotropic phase, ground bounce with the
// albedo) to get the second-order luminance L2 and the transfer factor f_ms,
// which includes the ground reflecting the isotropic field back; all orders
// follow from the geometric series Psi_ms = L2 / (1 - f_ms). f_ms is clamped to max_fms
// (dense atmospheres drive it to 1) and clamped texels are counted. The sun
// zenith axis is non-linear (MultiScatteringMapping), altitude is linear.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/lut_image.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

// The sun zenith cosine axis, mu_s in [-1, 1] <-> unit x in [0, 1], in three
// linear pieces. Below mu_s ~ 0 Psi falls exponentially into Earth's shadow (an
// e-fold per ~0.02 of mu_s near the ground): linear interpolation between
// uniform columns 0.065 apart overestimated it 2-4x there, which is where the
// sky of a sun below the horizon samples it. Above mu_s ~ 0.1 Psi is
// nearly linear and below -0.3 it is ~0, so [-0.3, 0.1] gets 18/31 of the axis
// (18 of a 32-wide LUT's 31 intervals), [0.1, 1] 11/31 and [-1, -0.3] 2/31.
struct MultiScatteringMapping {
  static constexpr float kShadowMu = -0.3f;  // the dense piece's ends
  static constexpr float kLitMu = 0.1f;
  static constexpr float kShadowUnit = 2.0f / 31.0f;  // and their unit x
  static constexpr float kLitUnit = 20.0f / 31.0f;

  // Selects, no division: inlined into the march's lookup loops, it vectorizes.
  static float to_unit(float mu_s) {
    constexpr float below = kShadowUnit / (kShadowMu + 1.0f);
    constexpr float dense = (kLitUnit - kShadowUnit) / (kLitMu - kShadowMu);
    constexpr float above = (1.0f - kLitUnit) / (1.0f - kLitMu);
    const float low = (mu_s + 1.0f) * below;
    const float mid = kShadowUnit + (mu_s - kShadowMu) * dense;
    const float high = kLitUnit + (mu_s - kLitMu) * above;
    return mu_s < kShadowMu ? low : (mu_s < kLitMu ? mid : high);
  }
  static float from_unit(float unit) {
    if (unit < kShadowUnit) return -1.0f + unit / kShadowUnit * (kShadowMu + 1.0f);
    if (unit < kLitUnit) return kShadowMu + (unit - kShadowUnit) / (kLitUnit - kShadowUnit) * (kLitMu - kShadowMu);
    return kLitMu + (unit - kLitUnit) / (1.0f - kLitUnit) * (1.0f - kLitMu);
  }
};

class MultiScatteringLut {
 public:
  MultiScatteringLut() = default;
  MultiScatteringLut(const AtmosphereModel& model, int size, int directions, int steps, float max_fms);

  // Texels [begin, end) (row-major: x = sun zenith, y = altitude).
  void bake(size_t begin, size_t end, const TransmittanceLut& transmittance);
  size_t texel_count() const { return image_.count(); }

  // Psi_ms for unit sun illuminance: in-scattered luminance per unit scattering coefficient.
  glm::vec3 sample(float altitude, float mu_s) const {
    return sample_bilinear(image_, MultiScatteringMapping::to_unit(mu_s) * float(image_.width - 1),
                           altitude * inv_top_altitude_ * float(image_.height - 1));
  }
  int clamped_texels() const;  // texels whose f_ms hit max_fms
  float max_fms_seen() const;  // largest unclamped f_ms component over the LUT

  const LutImage& image() const { return image_; }
  const float* packed() const { return packed_.data(); }  // the image as rgb + pad (see float4.h)

 private:
  AtmosphereModel model_;
  int directions_ = 64;
  int steps_ = 20;
  float max_fms_ = 0.95f;
  float inv_top_altitude_ = 0.0f;
  LutImage image_;
  std::vector<float> packed_;
  std::vector<uint8_t> clamped_;
  std::vector<float> fms_;
  glm::vec3 ground_irradiance_{0.0f};  // of the ground from a unit isotropic field: its share of f_ms
};

}  // namespace cr

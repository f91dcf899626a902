#pragma once
// LUT 2: Hillaire's multiple-scattering term Psi_ms over (sun zenith cosine,
// altitude). Per texel, `directions` rays are marched (sqrt(directions) polar
// bands, denser near the local horizon; isotropic phase, ground bounce with the
// albedo) to get the second-order luminance L2 and the transfer factor f_ms,
// which includes the ground reflecting the isotropic field back; all orders
// follow from the geometric series Psi_ms = L2 / (1 - f_ms). f_ms is clamped to max_fms
// (dense atmospheres drive it to 1) and clamped texels are counted.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/lut_image.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

class MultiScatteringLut {
 public:
  MultiScatteringLut() = default;
  MultiScatteringLut(const AtmosphereModel& model, int size, int directions, int steps, float max_fms);

  // Texels [begin, end) (row-major: x = sun zenith, y = altitude).
  void bake(size_t begin, size_t end, const TransmittanceLut& transmittance);
  size_t texel_count() const { return image_.count(); }

  // Psi_ms for unit sun illuminance: in-scattered luminance per unit scattering coefficient.
  glm::vec3 sample(float altitude, float mu_s) const {
    return sample_bilinear(image_, (mu_s * 0.5f + 0.5f) * float(image_.width - 1),
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

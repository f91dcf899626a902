#include "atmosphere/spectral_sampling.h"

#include <stdexcept>
#include <string>

#include "engine/core/colorimetry.h"
#include "atmosphere/reference_atmosphere.h"
#include "engine/core/spectral_tables.h"

namespace cr {

SpectralSampling rgb_sampling() {
  SpectralSampling s;
  s.rgb = true;
  for (int c = 0; c < 3; ++c) {
    s.wavelengths_nm.push_back(kRgbWavelengthsNm[c]);
    glm::dvec3 w(0.0);
    w[c] = 1.0;
    s.weights.push_back(w);
  }
  return s;
}

SpectralSampling band_sampling(double lo, double hi, int bands) {
  if (bands < 1 || !(hi > lo)) throw std::invalid_argument("band_sampling: need bands >= 1 and hi > lo");
  SpectralSampling s;
  const glm::dmat3 to_srgb = xyz_to_linear_srgb_matrix();
  glm::dvec3 total(0.0);
  const double width = (hi - lo) / bands;
  for (int b = 0; b < bands; ++b) {
    const double a = lo + b * width;
    s.wavelengths_nm.push_back(a + 0.5 * width);
    s.weights.push_back(to_srgb * band_xyz(solar_irradiance_toa(), a, a + width));
    total += s.weights.back();
  }
  for (glm::dvec3& w : s.weights) w /= total;
  while (s.wavelengths_nm.size() % 3 != 0) {  // padding: repeats the last band with no weight
    s.wavelengths_nm.push_back(s.wavelengths_nm.back());
    s.weights.push_back(glm::dvec3(0.0));
  }
  return s;
}

SpectralSampling lut_sampling(int samples) {
  if (samples == 3) return rgb_sampling();
  if (samples < 3 || samples % 3 != 0) throw std::invalid_argument("spectral_samples must be 3 or a multiple of 3");
  return band_sampling(380.0, 780.0, samples);
}

SpectralSampling reference_sampling() { return band_sampling(360.0, 830.0, 47); }

glm::dvec3 to_rgb(const SpectralSampling& s, const std::vector<glm::dvec3>& group_values) {
  glm::dvec3 rgb(0.0);
  for (size_t i = 0; i < s.wavelengths_nm.size(); ++i) rgb += s.weights[i] * group_values[i / 3][int(i % 3)];
  return rgb;
}

}  // namespace cr

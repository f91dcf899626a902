#include "atmosphere/colorimetry.h"

#include <cstddef>

namespace cr {

namespace {

// The colour-matching functions at wavelength w (a 5-nm sample; 0 outside the table).
glm::dvec3 cmf_at(double w) {
  for (const CmfSample& s : cie1931_cmf())
    if (s.wavelength_nm == w) return {s.x, s.y, s.z};
  return glm::dvec3(0.0);
}

// XYZ of chromaticity (x, y) at luminance Y = 1.
glm::dvec3 xyz_of(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

}  // namespace

glm::dvec3 spectrum_to_xyz(std::span<const SpectralSample> bins) {
  glm::dvec3 xyz(0.0);
  for (const SpectralSample& b : bins) {
    const double w = b.wavelength_nm;
    // Trapezoids on [w, w + 5] and [w + 5, w + 10].
    const glm::dvec3 integral = 2.5 * (cmf_at(w) + 2.0 * cmf_at(w + 5.0) + cmf_at(w + 10.0));
    xyz += b.value * integral;
  }
  return xyz;
}

glm::dmat3 xyz_to_linear_srgb_matrix() {
  // Columns: the primaries' XYZ at unit luminance, scaled so that they add up to D65 white.
  const glm::dmat3 primaries(xyz_of(0.64, 0.33), xyz_of(0.30, 0.60), xyz_of(0.15, 0.06));
  const glm::dvec3 scale = glm::inverse(primaries) * xyz_of(0.3127, 0.3290);
  const glm::dmat3 rgb_to_xyz(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
  return glm::inverse(rgb_to_xyz);
}

}  // namespace cr

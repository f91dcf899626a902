#include "engine/core/colorimetry.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cr {

namespace {

// The colour-matching functions at a tabulated wavelength (0 outside the table).
glm::dvec3 cmf_sample(double w) {
  for (const CmfSample& s : cie1931_cmf())
    if (s.wavelength_nm == w) return {s.x, s.y, s.z};
  return glm::dvec3(0.0);
}

// The bin's mean value at w (0 outside every bin).
double bin_value(std::span<const SpectralSample> bins, double w) {
  for (const SpectralSample& b : bins)
    if (w >= b.wavelength_nm && w < b.wavelength_nm + 10.0) return b.value;
  return 0.0;
}

// XYZ of chromaticity (x, y) at luminance Y = 1.
glm::dvec3 xyz_of(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

}  // namespace

glm::dvec3 spectrum_to_xyz(std::span<const SpectralSample> bins) {
  glm::dvec3 xyz(0.0);
  for (const SpectralSample& b : bins) {
    const double w = b.wavelength_nm;
    // Trapezoids on [w, w + 5] and [w + 5, w + 10].
    const glm::dvec3 integral = 2.5 * (cmf_sample(w) + 2.0 * cmf_sample(w + 5.0) + cmf_sample(w + 10.0));
    xyz += b.value * integral;
  }
  return xyz;
}

glm::dvec3 cmf_at(double w) {
  const std::span<const CmfSample> t = cie1931_cmf();
  if (!(w >= t.front().wavelength_nm && w <= t.back().wavelength_nm)) return glm::dvec3(0.0);
  const size_t i = std::min(t.size() - 2, size_t((w - t.front().wavelength_nm) / 5.0));
  const double f = (w - t[i].wavelength_nm) / (t[i + 1].wavelength_nm - t[i].wavelength_nm);
  const glm::dvec3 a(t[i].x, t[i].y, t[i].z), b(t[i + 1].x, t[i + 1].y, t[i + 1].z);
  return a + (b - a) * f;
}

glm::dvec3 band_xyz(std::span<const SpectralSample> bins, double lo, double hi) {
  // Midpoints of 0.25-nm steps: exact for the linear colour-matching
  // functions, and the spectrum's bin edges fall within 0.125 nm of a step edge.
  const int steps = std::max(1, int(std::ceil((hi - lo) / 0.25)));
  const double h = (hi - lo) / steps;
  glm::dvec3 xyz(0.0);
  for (int k = 0; k < steps; ++k) {
    const double w = lo + (k + 0.5) * h;
    xyz += bin_value(bins, w) * cmf_at(w) * h;
  }
  return xyz;
}

double solar_illuminance_lux() {
  static const double lux = kLuminousEfficacy * spectrum_to_xyz(solar_irradiance_toa()).y;
  return lux;
}

glm::dvec3 solar_color() {
  static const glm::dvec3 color = [] {
    const glm::dvec3 xyz = spectrum_to_xyz(solar_irradiance_toa());
    return xyz_to_linear_srgb_matrix() * xyz / xyz.y;
  }();
  return color;
}

glm::dmat3 xyz_to_linear_srgb_matrix() {
  // Columns: the primaries' XYZ at unit luminance, scaled so that they add up to D65 white.
  const glm::dmat3 primaries(xyz_of(0.64, 0.33), xyz_of(0.30, 0.60), xyz_of(0.15, 0.06));
  const glm::dvec3 scale = glm::inverse(primaries) * xyz_of(0.3127, 0.3290);
  const glm::dmat3 rgb_to_xyz(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
  return glm::inverse(rgb_to_xyz);
}

}  // namespace cr

#include "atmosphere/model_spectrum.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/reference_atmosphere.h"

namespace cr {

namespace {

// A coefficient given at the three channel wavelengths (descending: 680, 550,
// 440 nm), at wavelength w: the power law through the two nearest channels,
// or the straight line where a value is not positive.
double channel_law(const glm::vec3& v, double w) {
  const int a = w >= kRgbWavelengthsNm[1] ? 0 : 1;  // segment [R, G] or [G, B]
  const double wa = kRgbWavelengthsNm[a], wb = kRgbWavelengthsNm[a + 1];
  const double va = v[a], vb = v[a + 1];
  if (va == vb) return va;
  if (va > 0.0 && vb > 0.0) return va * std::pow(w / wa, std::log(vb / va) / std::log(wb / wa));
  return std::max(0.0, va + (vb - va) * (w - wa) / (wb - wa));
}

}  // namespace

SpectralCoefficients coefficients_at(const AtmosphereModel& m, double w) {
  double num = 0.0, den = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double sigma = ozone_cross_section_at(kRgbWavelengthsNm[c]);
    num += double(m.ozone_absorption[c]) * sigma;
    den += sigma * sigma;
  }
  const double ozone_density = den > 0.0 ? num / den : 0.0;
  return {channel_law(m.rayleigh_scattering, w), channel_law(m.mie_scattering, w), channel_law(m.mie_absorption, w),
          ozone_density * ozone_cross_section_at(w)};
}

AtmosphereModel model_at_wavelengths(const AtmosphereModel& m, const std::array<double, 3>& wavelengths_nm) {
  AtmosphereModel out = m;
  for (int c = 0; c < 3; ++c) {
    const SpectralCoefficients k = coefficients_at(m, wavelengths_nm[size_t(c)]);
    out.rayleigh_scattering[c] = float(k.rayleigh_scattering);
    out.mie_scattering[c] = float(k.mie_scattering);
    out.mie_absorption[c] = float(k.mie_absorption);
    out.ozone_absorption[c] = float(k.ozone_absorption);
  }
  return out;
}

}  // namespace cr

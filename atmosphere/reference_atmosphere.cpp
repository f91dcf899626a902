#include "atmosphere/reference_atmosphere.h"

#include <cmath>

#include "engine/core/spectral_tables.h"
#include "engine/core/math_constants.h"

namespace cr {

namespace {
constexpr double kDobsonUnit = 2.687e20;  // molecules per m^2 of column
}

double reference_rayleigh(double wavelength_nm) { return 1.24062e-6 * std::pow(wavelength_nm / 1000.0, -4.0); }

double ozone_peak_density(double dobson, double half_width_m) {
  return dobson * kDobsonUnit / half_width_m;  // a tent's column is its peak times its half width
}

double ozone_cross_section_at(double wavelength_nm) {
  for (const SpectralSample& s : ozone_cross_section())
    if (wavelength_nm >= s.wavelength_nm && wavelength_nm < s.wavelength_nm + 10.0) return s.value;
  return 0.0;
}

AtmosphereModel reference_atmosphere() {
  AtmosphereModel m;
  m.bottom_radius = 6360e3;
  m.top_radius = 6420e3;
  m.ground_albedo = glm::vec3(0.1f);
  m.rayleigh_scale_height = 8000.0f;
  m.mie_scale_height = 1200.0f;
  m.mie_phase = MiePhaseModel::CornetteShanks;
  m.mie_g = 0.8f;
  const double mie_extinction = 4.44e-6, mie_albedo = 0.9;
  m.ozone_center = 25000.0f;
  m.ozone_half_width = 15000.0f;
  const double ozone = ozone_peak_density(300.0, m.ozone_half_width);
  for (int c = 0; c < 3; ++c) {
    m.rayleigh_scattering[c] = float(reference_rayleigh(kRgbWavelengthsNm[c]));
    m.mie_scattering[c] = float(mie_extinction * mie_albedo);
    m.mie_absorption[c] = float(mie_extinction * (1.0 - mie_albedo));
    m.ozone_absorption[c] = float(ozone * ozone_cross_section_at(kRgbWavelengthsNm[c]));
  }
  m.sun_angular_radius = float(0.2678 * kPiD / 180.0);
  return m;
}

}  // namespace cr

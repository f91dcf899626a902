#pragma once
// Measured spectra for the spectral sky (engine/data/spectral/, sources in
// its README), compiled in by the build from the CSV files.
#include <span>

namespace cr {

// CIE 1931 2-degree observer at one wavelength (360-830 nm every 5 nm).
struct CmfSample {
  double wavelength_nm, x, y, z;
};

// A 10-nm bin starting at wavelength_nm (360-830 nm): its mean value.
struct SpectralSample {
  double wavelength_nm, value;
};

std::span<const CmfSample> cie1931_cmf();
std::span<const SpectralSample> solar_irradiance_toa();  // W m^-2 nm^-1 (ASTM G-173-03 ETR)
std::span<const SpectralSample> ozone_cross_section();   // m^2 per molecule at 233 K

}  // namespace cr

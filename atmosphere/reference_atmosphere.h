#pragma once
// The reference atmosphere (preset "reference"): the one the spectral
// references in the literature use (Bruneton 2017's demo), so that the LUT
// method can be compared like with like. Bottom 6360 km, top 6420 km,
// ground albedo 0.1; Rayleigh 1.24062e-6 (lambda / 1 um)^-4 /m, scale height
// 8 km; Mie extinction 4.44e-6 /m at every wavelength, single-scattering
// albedo 0.9, scale height 1.2 km, Cornette-Shanks g 0.8; 300 Dobson units
// of ozone in a tent from 10 to 40 km peaking at 25 km; sun radius 0.2678 deg.
// The RGB channels are the wavelengths kRgbWavelengthsNm; the ozone cross
// sections come from the measured spectrum (spectral_tables.h).
#include "atmosphere/atmosphere_model.h"

namespace cr {

inline constexpr double kRgbWavelengthsNm[3] = {680.0, 550.0, 440.0};

AtmosphereModel reference_atmosphere();

// Rayleigh scattering of the reference atmosphere at sea level, /m.
double reference_rayleigh(double wavelength_nm);
// Peak ozone number density (molecules / m^3) of `dobson` Dobson units in a tent of this half width (m).
double ozone_peak_density(double dobson, double half_width_m);
// The ozone cross-section (m^2) of the 10-nm bin holding the wavelength; 0 outside 360-840 nm.
double ozone_cross_section_at(double wavelength_nm);

}  // namespace cr

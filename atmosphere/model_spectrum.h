#pragma once
// An RGB atmosphere model extended across the spectrum. Its three channels
// are the wavelengths kRgbWavelengthsNm (680, 550, 440 nm); between and
// beyond them each scattering and absorption coefficient follows the power
// law through its two nearest channels (exact for Rayleigh's lambda^-4 and a
// grey or Angstrom-law aerosol), and ozone follows the measured
// cross-section scaled to the channels (a least-squares fit; exact for the
// Earth presets, whose ozone is that cross-section at 300 DU).
#include <array>

#include "atmosphere/atmosphere_model.h"

namespace cr {

struct SpectralCoefficients {
  double rayleigh_scattering, mie_scattering, mie_absorption, ozone_absorption;  // /m at the ground or peak
};

SpectralCoefficients coefficients_at(const AtmosphereModel& m, double wavelength_nm);

// The model with its three channels moved to these wavelengths (all else kept):
// the RGB kernels run on it unchanged.
AtmosphereModel model_at_wavelengths(const AtmosphereModel& m, const std::array<double, 3>& wavelengths_nm);

}  // namespace cr

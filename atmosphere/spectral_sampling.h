#pragma once
// How the sky is sampled across the spectrum, and how the samples become
// linear sRGB. A sampling is a list of wavelengths in groups of three (each
// group runs the RGB kernels unchanged, with a model at those wavelengths:
// model_spectrum.h) and, per wavelength, the linear sRGB it contributes per
// unit of response: the solar spectrum times the CIE 1931 observer
// integrated over its band (Bruneton 2017's luminance conversion done per
// band), normalised so that each channel's weights add up to 1. A response
// of 1 at every wavelength (no atmosphere) is then exactly (1, 1, 1): the
// LUTs keep storing radiance per unit of sun illuminance in each channel,
// and a transmittance converts by the same weights (the sunlight's own).
#include <vector>

#include <glm/glm.hpp>

namespace cr {

struct SpectralSampling {
  std::vector<double> wavelengths_nm;  // a multiple of 3; a band's representative wavelength
  std::vector<glm::dvec3> weights;     // per wavelength: its share of each sRGB channel
  bool rgb = false;                    // the RGB model itself: 680/550/440 nm, identity weights
  int groups() const { return int(wavelengths_nm.size() / 3); }
};

// Today's three-channel model (kRgbWavelengthsNm) with identity weights.
SpectralSampling rgb_sampling();
// `bands` equal bands over [lo, hi] nm, each at its centre wavelength, padded
// with zero-weight samples to a multiple of 3.
SpectralSampling band_sampling(double lo_nm, double hi_nm, int bands);
// The LUT option "spectral_samples": 3 is rgb_sampling(), more are bands over 380-780 nm.
SpectralSampling lut_sampling(int samples);
// The reference's: the 47 10-nm bins of the measured spectra from 360 to 830 nm.
SpectralSampling reference_sampling();

// Combines per-wavelength values (groups of three, in the sampling's order) into linear sRGB.
glm::dvec3 to_rgb(const SpectralSampling& s, const std::vector<glm::dvec3>& group_values);

}  // namespace cr

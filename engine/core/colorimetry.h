#pragma once
// From spectra to colour: the CIE 1931 2-degree observer over bin-averaged
// spectra (spectral_tables.h), photometric luminance, and linear sRGB (the
// IEC 61966-2-1 primaries and D65 white) derived from its chromaticities
// rather than typed in.
#include <span>

#include <glm/glm.hpp>

#include "engine/core/spectral_tables.h"

namespace cr {

inline constexpr double kLuminousEfficacy = 683.0;  // lm/W at 555 nm: photometric Y = 683 * CIE Y

// CIE XYZ of a spectrum given as 10-nm bin means (each bin starting at its
// wavelength): per bin its value times the colour-matching functions
// integrated over the bin (trapezoids on the 5-nm samples; 0 past 830 nm).
glm::dvec3 spectrum_to_xyz(std::span<const SpectralSample> bins);

// The colour-matching functions at any wavelength: linear between the 5-nm
// samples, 0 outside 360-830 nm.
glm::dvec3 cmf_at(double wavelength_nm);

// CIE XYZ of the part of a bin-mean spectrum between lo and hi (nm): the
// integral of spectrum x colour-matching functions over [lo, hi].
glm::dvec3 band_xyz(std::span<const SpectralSample> bins, double lo_nm, double hi_nm);

// The 3x3 matrix from CIE XYZ to linear sRGB, built from the sRGB primaries'
// and D65's chromaticities (so that Y of each primary sums to 1 at white).
glm::dmat3 xyz_to_linear_srgb_matrix();

// The sun at the top of the atmosphere from the measured solar spectrum
// (ASTM G-173-03): its illuminance, 683 lm/W x the integral of E(lambda)
// ybar(lambda) (about 133,200 lx), and its linear sRGB colour at unit
// luminance (x 0.324, y 0.333: a little warmer than D65). The scene's sun
// defaults to these.
double solar_illuminance_lux();
glm::dvec3 solar_color();

}  // namespace cr

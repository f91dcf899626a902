// The spectral tables and colorimetry: closed forms and published values.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "atmosphere/atmosphere_model.h"
#include "engine/core/colorimetry.h"
#include "atmosphere/reference_atmosphere.h"
#include "engine/core/luminance.h"

using namespace cr;

TEST_CASE("spectral tables: the build compiled the CSV files whole") {
  CHECK(cie1931_cmf().size() == 95);  // 360-830 nm every 5 nm
  CHECK(cie1931_cmf().front().wavelength_nm == 360.0);
  CHECK(cie1931_cmf().back().wavelength_nm == 830.0);
  CHECK(solar_irradiance_toa().size() == 48);  // 10-nm bins from 360 to 830 nm
  CHECK(ozone_cross_section().size() == 48);
  // The observer's luminosity peak: ybar = 1 at 555 nm.
  for (const CmfSample& s : cie1931_cmf())
    if (s.wavelength_nm == 555.0) CHECK(s.y == doctest::Approx(1.0).epsilon(1e-3));
}

TEST_CASE("colorimetry: the integral of ybar is the published 106.86 nm, an equal-energy spectrum is white") {
  std::vector<SpectralSample> flat;
  for (const SpectralSample& b : solar_irradiance_toa()) flat.push_back({b.wavelength_nm, 1.0});
  const glm::dvec3 e = spectrum_to_xyz(flat);
  // CIE: the sum of ybar over 360-830 nm at 1-nm steps is 106.857 (x, z likewise 106.866, 106.892).
  CHECK(e.y == doctest::Approx(106.857).epsilon(2e-3));
  CHECK(e.x == doctest::Approx(106.866).epsilon(2e-3));
  CHECK(e.z == doctest::Approx(106.892).epsilon(2e-3));
}

TEST_CASE("colorimetry: the derived XYZ to sRGB matrix is IEC 61966-2-1's and sends D65 to equal RGB") {
  const glm::dmat3 m = xyz_to_linear_srgb_matrix();
  // The standard's rounded matrix (rows), as published.
  const double published[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) CHECK(m[c][r] == doctest::Approx(published[r][c]).epsilon(1e-3));
  const glm::dvec3 white = m * glm::dvec3(0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290);
  CHECK(white.r == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(white.g == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(white.b == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("colorimetry: the top-of-atmosphere sun is 128-133 klx, and its sRGB luminance reproduces Y within 0.1%") {
  const glm::dvec3 xyz = spectrum_to_xyz(solar_irradiance_toa());
  const double lux = kLuminousEfficacy * xyz.y;
  MESSAGE("solar spectrum at the top of the atmosphere: " << lux << " lx, xy = (" << xyz.x / (xyz.x + xyz.y + xyz.z)
                                                          << ", " << xyz.y / (xyz.x + xyz.y + xyz.z) << ")");
  CHECK(lux > 125000.0);
  CHECK(lux < 135000.0);
  const glm::dvec3 rgb = xyz_to_linear_srgb_matrix() * xyz;
  CHECK(luminance(rgb) == doctest::Approx(xyz.y).epsilon(1e-3));
}

TEST_CASE("reference atmosphere preset: the literature's constants, ozone from the measured cross-sections") {
  const AtmosphereModel m = atmosphere_preset("reference");
  CHECK(m.bottom_radius == 6360e3);
  CHECK(m.top_radius == 6420e3);
  CHECK(m.ground_albedo == glm::vec3(0.1f));
  // Rayleigh 1.24062e-6 (lambda / 1 um)^-4 at 680, 550, 440 nm: the Earth defaults' (5.802, 13.558, 33.1)e-6.
  CHECK(m.rayleigh_scattering.x == doctest::Approx(5.802e-6).epsilon(1e-3));
  CHECK(m.rayleigh_scattering.y == doctest::Approx(13.558e-6).epsilon(1e-3));
  CHECK(m.rayleigh_scattering.z == doctest::Approx(33.1e-6).epsilon(1e-3));
  // Mie extinction 4.44e-6 with single-scattering albedo 0.9.
  CHECK(m.mie_scattering.y + m.mie_absorption.y == doctest::Approx(4.44e-6).epsilon(1e-6));
  CHECK(m.mie_scattering.y / (m.mie_scattering.y + m.mie_absorption.y) == doctest::Approx(0.9).epsilon(1e-6));
  // 300 DU in a 10-40 km tent: the column is 300 x 2.687e20 molecules / m^2.
  CHECK(ozone_peak_density(300.0, m.ozone_half_width) * m.ozone_half_width == doctest::Approx(300.0 * 2.687e20));
  CHECK(m.ozone_absorption.y == doctest::Approx(ozone_peak_density(300.0, 15000.0) * 3.5e-25).epsilon(1e-6));
  CHECK(m.ozone_center - m.ozone_half_width == 10000.0f);
  CHECK(m.ozone_center + m.ozone_half_width == 40000.0f);
  CHECK(m.sun_angular_radius == doctest::Approx(0.2678 * 3.14159265358979 / 180.0).epsilon(1e-6));
}

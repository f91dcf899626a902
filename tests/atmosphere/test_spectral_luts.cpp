// The spectral option of the LUTs: the sampling's conversion to sRGB, the
// model's extension across the spectrum, and LUTs baked in wavelength groups.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/model_spectrum.h"
#include "atmosphere/reference_atmosphere.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere/spectral_sampling.h"
#include "atmosphere_test_util.h"
#include "engine/core/colorimetry.h"
#include "engine/core/error.h"
#include "engine/core/luminance.h"
#include "engine/scene/scene_description.h"

using namespace cr;
using namespace cr::test;

namespace {

// Sky radiance over a small panorama for a scheduler's published LUTs.
std::vector<glm::vec3> panorama(const AtmosphereSettings& settings, const SpectralSampling* sampling, double sun_zenith,
                                unsigned threads) {
  LutScheduler s = sampling ? LutScheduler(settings, *sampling) : LutScheduler(settings);
  JobSystem jobs(threads);
  const Camera cam = camera_at(2.0);
  const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(sun_zenith), jobs);
  const SkyFrame f = frame_of(s, p, cam);
  std::vector<glm::vec3> out;
  for (int e = 0; e < 8; ++e)
    for (int a = 0; a < 16; ++a) {
      const double el = (1.0 + 11.0 * e) * kPiD / 180.0, az = a * 2.0 * kPiD / 16.0;
      const glm::vec3 d(float(std::cos(el) * std::cos(az)), float(std::sin(el)), float(std::cos(el) * std::sin(az)));
      out.push_back(sky_radiance(f, d, false));
    }
  return out;
}

double max_relative_difference(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(double(a[i][c]) - double(b[i][c])) / std::max(1e-6, double(b[i][c])));
  return worst;
}

// Mean over the panorama of |(x/g)_a / (x/g)_b - 1| for channel x (0: red, 2: blue).
double ratio_error(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b, int channel) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::abs((a[i][channel] / a[i].g) / (b[i][channel] / b[i].g) - 1.0);
  return sum / double(a.size());
}

}  // namespace

TEST_CASE("spectral sampling: a flat response mixes to white, and the bands integrate the whole sun") {
  for (const SpectralSampling& s : {lut_sampling(6), lut_sampling(12), lut_sampling(15), reference_sampling()}) {
    CHECK(s.wavelengths_nm.size() % 3 == 0);
    std::vector<glm::dvec3> ones(size_t(s.groups()), glm::dvec3(1.0));
    const glm::dvec3 white = to_rgb(s, ones);
    for (int c = 0; c < 3; ++c) CHECK(white[c] == doctest::Approx(1.0).epsilon(1e-12));
  }
  // The band integrals over 360-830 nm add up to the spectrum's XYZ (one quadrature against the other).
  const glm::dvec3 whole = spectrum_to_xyz(solar_irradiance_toa());
  glm::dvec3 bands(0.0);
  for (int b = 0; b < 47; ++b) bands += band_xyz(solar_irradiance_toa(), 360.0 + 10.0 * b, 370.0 + 10.0 * b);
  for (int c = 0; c < 3; ++c) CHECK(bands[c] == doctest::Approx(whole[c]).epsilon(1e-3));
  // The 3-sample option is the RGB model itself.
  const SpectralSampling rgb = lut_sampling(3);
  CHECK(rgb.rgb);
  CHECK(rgb.wavelengths_nm == std::vector<double>{680.0, 550.0, 440.0});
  CHECK_THROWS(lut_sampling(4));
}

TEST_CASE("the sun at the top of the atmosphere from the solar spectrum: 133 klx, a warm white") {
  const double lux = solar_illuminance_lux();
  const glm::dvec3 c = solar_color();
  MESSAGE("solar illuminance " << lux << " lx, linear sRGB colour " << c.r << ", " << c.g << ", " << c.b);
  CHECK(lux == doctest::Approx(kLuminousEfficacy * spectrum_to_xyz(solar_irradiance_toa()).y));
  CHECK(luminance(c) == doctest::Approx(1.0).epsilon(1e-4));  // the Y row is rounded to 4 digits
  CHECK(c.r > c.g);  // x 0.324 > D65's 0.313: warmer than the sRGB white
  CHECK(c.g > c.b);
}

TEST_CASE("model spectrum: the channels reproduced, Rayleigh's lambda^-4, a grey aerosol and the ozone spectrum") {
  const AtmosphereModel earth;
  for (int c = 0; c < 3; ++c) {
    const SpectralCoefficients k = coefficients_at(earth, kRgbWavelengthsNm[c]);
    CHECK(k.rayleigh_scattering == doctest::Approx(earth.rayleigh_scattering[c]).epsilon(1e-6));
    CHECK(k.mie_scattering == doctest::Approx(earth.mie_scattering[c]).epsilon(1e-6));
    CHECK(k.ozone_absorption == doctest::Approx(earth.ozone_absorption[c]).epsilon(1e-3));
  }
  for (double w : {380.0, 470.0, 600.0, 760.0}) {
    const SpectralCoefficients k = coefficients_at(earth, w);
    CHECK(k.rayleigh_scattering == doctest::Approx(reference_rayleigh(w)).epsilon(2e-3));
    CHECK(k.mie_scattering == doctest::Approx(earth.mie_scattering.g).epsilon(1e-6));
    CHECK(k.ozone_absorption ==
          doctest::Approx(ozone_peak_density(300.0, earth.ozone_half_width) * ozone_cross_section_at(w)).epsilon(2e-3));
  }
  // An Angstrom-law aerosol (exponent 1.3) stays one.
  AtmosphereModel hazy = earth;
  for (int c = 0; c < 3; ++c) hazy.mie_scattering[c] = float(4e-6 * std::pow(kRgbWavelengthsNm[c] / 550.0, -1.3));
  CHECK(coefficients_at(hazy, 500.0).mie_scattering == doctest::Approx(4e-6 * std::pow(500.0 / 550.0, -1.3)).epsilon(1e-5));
  CHECK(coefficients_at(hazy, 720.0).mie_scattering == doctest::Approx(4e-6 * std::pow(720.0 / 550.0, -1.3)).epsilon(1e-5));
}

TEST_CASE("spectral LUTs: three wavelengths through the group machinery are today's RGB LUTs") {
  SpectralSampling three;
  three.wavelengths_nm = {680.0, 550.0, 440.0};
  three.weights = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const AtmosphereSettings settings = small_settings();
  for (double zenith : {30.0, 93.0}) {
    const std::vector<glm::vec3> rgb = panorama(settings, nullptr, zenith, 2);
    const std::vector<glm::vec3> grouped = panorama(settings, &three, zenith, 2);
    CHECK(max_relative_difference(grouped, rgb) < 1e-4);
  }
}

TEST_CASE("spectral LUTs: close to RGB by day, a different colour at twilight, and the same bits on any thread count") {
  AtmosphereSettings settings = small_settings();
  settings.spectral_samples = 15;
  const AtmosphereSettings rgb_settings = small_settings();
  const std::vector<glm::vec3> day = panorama(settings, nullptr, 30.0, 1);
  const std::vector<glm::vec3> day_rgb = panorama(rgb_settings, nullptr, 30.0, 1);
  double y_err = 0.0;
  for (size_t i = 0; i < day.size(); ++i) y_err += std::abs(luminance(day[i]) / luminance(day_rgb[i]) - 1.0f);
  y_err /= double(day.size());
  const std::vector<glm::vec3> dusk = panorama(settings, nullptr, 93.0, 1);
  const std::vector<glm::vec3> dusk_rgb = panorama(rgb_settings, nullptr, 93.0, 1);
  const double rg = ratio_error(dusk_rgb, dusk, 0);
  MESSAGE("15 samples against RGB: day luminance " << 100 * y_err << "%, twilight r/g " << 100 * rg << "%");
  CHECK(y_err < 0.05);
  CHECK(rg > 0.1);
  CHECK(panorama(settings, nullptr, 93.0, 2) == dusk);
}

TEST_CASE("spectral_samples: 3 or a multiple of 3, up to 48") {
  auto parse = [](int n) { return parse_atmosphere_settings(nlohmann::json{{"spectral_samples", n}}, "p.json"); };
  CHECK(parse(3).spectral_samples == 3);
  CHECK(parse(12).spectral_samples == 12);
  CHECK_THROWS_AS(parse(4), InputError);
  CHECK_THROWS_AS(parse(0), InputError);
  CHECK_THROWS_AS(parse(51), InputError);
}

TEST_CASE("Earth's defaults: Mie extinction 4.44e-6 at albedo 0.9, and the sun of the solar spectrum") {
  const AtmosphereModel earth = atmosphere_preset("earth-clear");
  CHECK(earth.mie_scattering.g + earth.mie_absorption.g == doctest::Approx(4.44e-6).epsilon(1e-6));
  CHECK(earth.mie_absorption.g == doctest::Approx(0.444e-6).epsilon(1e-6));
  CHECK(earth.mie_scattering.g / (earth.mie_scattering.g + earth.mie_absorption.g) == doctest::Approx(0.9).epsilon(1e-6));
  const SunSpec sun;
  CHECK(sun.illuminance == doctest::Approx(solar_illuminance_lux()).epsilon(1e-6));
  CHECK(sun.illuminance == doctest::Approx(133182.0).epsilon(1e-4));
  for (int c = 0; c < 3; ++c) CHECK(sun.color[c] == doctest::Approx(solar_color()[c]).epsilon(1e-6));
}

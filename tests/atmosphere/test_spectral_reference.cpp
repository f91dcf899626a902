// The full-spectral reference renderer: its spectral machinery reduces to the
// RGB reference, single scattering does not depend on how the wavelengths are
// grouped, the spectrum matters at twilight, and any thread count gives the
// same bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/reference_atmosphere.h"
#include "atmosphere/spectral_sampling.h"
#include "atmosphere/tools/reference_renderer.h"
#include "atmosphere/tools/sky_case.h"
#include "engine/core/luminance.h"
#include "engine/core/math_constants.h"

using namespace cr;

namespace {

// Directions at these elevations (deg), at azimuth `azimuth_deg` from the sun's (the sun is at azimuth 0: +x).
std::vector<glm::vec3> directions(const std::vector<double>& elevations_deg, double azimuth_deg) {
  std::vector<glm::vec3> d;
  const double a = azimuth_deg * kPiD / 180.0;
  for (double el : elevations_deg) {
    const double e = el * kPiD / 180.0;
    d.push_back(glm::vec3(float(std::cos(e) * std::cos(a)), float(std::sin(e)), float(std::cos(e) * std::sin(a))));
  }
  return d;
}

ReferenceView view_at(const AtmosphereModel& m, double altitude, double sun_zenith_deg, std::vector<glm::vec3> dirs) {
  ReferenceView v;
  v.origin = glm::dvec3(0.0, m.bottom_radius + altitude, 0.0);
  v.directions = std::move(dirs);
  v.sun_direction = sun_at_zenith_angle(sun_zenith_deg);
  v.sun_illuminance = glm::vec3(solar_color() * solar_illuminance_lux());
  return v;
}

ReferenceImage render(const AtmosphereModel& m, const ReferenceView& v, const SpectralSampling& sampling, int spp,
                      bool single, bool multiple, unsigned threads = 1) {
  ReferenceSettings s;
  s.sampling = sampling;
  s.samples_per_pixel = spp;
  s.single_scattering = single;
  s.multiple_scattering = multiple;
  JobSystem jobs(threads);
  return render_reference(m, v, s, jobs, {});
}

// 680/550/440 nm with identity weights, through the spectral path (rgb = false).
SpectralSampling rgb_wavelengths_as_spectral() {
  SpectralSampling s = rgb_sampling();
  s.rgb = false;
  return s;
}

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-30); }

}  // namespace

TEST_CASE("spectral reference: one wavelength per channel equals the RGB reference (single scattering 1e-4, paths within noise)") {
  const AtmosphereModel m = atmosphere_preset("earth-clear");
  const ReferenceView v = view_at(m, 1000.0, 60.0, directions({-5.0, 2.0, 10.0, 45.0, 85.0}, 30.0));
  const ReferenceImage rgb_ss = render(m, v, rgb_sampling(), 0, true, false);
  const ReferenceImage spec_ss = render(m, v, rgb_wavelengths_as_spectral(), 0, true, false);
  double worst = 0.0;
  for (size_t i = 0; i < v.directions.size(); ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, rel(spec_ss.radiance[i][c], rgb_ss.radiance[i][c]));
  MESSAGE("single scattering: largest relative difference " << worst);
  CHECK(worst < 1e-4);

  const ReferenceImage rgb_ms = render(m, v, rgb_sampling(), 64, false, true);
  const ReferenceImage spec_ms = render(m, v, rgb_wavelengths_as_spectral(), 64, false, true);
  for (size_t i = 0; i < v.directions.size(); ++i) {
    const double y_rgb = luminance(glm::dvec3(rgb_ms.radiance[i])), y_spec = luminance(glm::dvec3(spec_ms.radiance[i]));
    const double sigma = std::hypot(double(rgb_ms.noise[i]), double(spec_ms.noise[i]));
    CAPTURE(i);
    CHECK(y_rgb > 0.0);
    CHECK(std::abs(y_spec - y_rgb) <= 3.0 * sigma + 1e-4 * y_rgb);
  }
}

TEST_CASE("spectral reference: single scattering does not depend on the grouping of the wavelengths") {
  const AtmosphereModel m = atmosphere_preset("reference");
  const ReferenceView v = view_at(m, 10.0, 80.0, directions({-3.0, 1.0, 20.0, 70.0}, 0.0));
  const SpectralSampling bands = reference_sampling();
  // The same bands in another order: reversed, so every group holds other wavelengths.
  SpectralSampling permuted = bands;
  std::reverse(permuted.wavelengths_nm.begin(), permuted.wavelengths_nm.end());
  std::reverse(permuted.weights.begin(), permuted.weights.end());
  const ReferenceImage a = render(m, v, bands, 0, true, false);
  const ReferenceImage b = render(m, v, permuted, 0, true, false);
  for (size_t i = 0; i < v.directions.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      CAPTURE(i);
      CHECK(a.radiance[i][c] > 0.0f);
      CHECK(rel(b.radiance[i][c], a.radiance[i][c]) < 1e-6);
    }
}

TEST_CASE("spectral reference: close to the RGB one by day, clearly less red at twilight") {
  const AtmosphereModel m = atmosphere_preset("reference");
  // Day: sun at the zenith, sky at 20-80 deg elevation. Single scattering (exact) within a few %, and
  // with the paths within their noise plus the same margin.
  const ReferenceView day = view_at(m, 1.0, 0.0, directions({20.0, 50.0, 80.0}, 90.0));
  const ReferenceImage ss_rgb = render(m, day, rgb_sampling(), 0, true, false, 2);
  const ReferenceImage ss_spec = render(m, day, reference_sampling(), 0, true, false, 2);
  const ReferenceImage day_rgb = render(m, day, rgb_sampling(), 64, true, true, 2);
  const ReferenceImage day_spec = render(m, day, reference_sampling(), 64, true, true, 2);
  for (size_t i = 0; i < day.directions.size(); ++i) {
    const double y_ss_rgb = luminance(glm::dvec3(ss_rgb.radiance[i])), y_ss_spec = luminance(glm::dvec3(ss_spec.radiance[i]));
    const double y_rgb = luminance(glm::dvec3(day_rgb.radiance[i])), y_spec = luminance(glm::dvec3(day_spec.radiance[i]));
    const double sigma = std::hypot(double(day_rgb.noise[i]), double(day_spec.noise[i]));
    MESSAGE("sun zenith 0 deg, pixel " << i << ": luminance spectral / RGB - 1: single scattering "
                                       << 100 * (y_ss_spec / y_ss_rgb - 1.0) << "%, all orders "
                                       << 100 * (y_spec / y_rgb - 1.0) << "% (noise " << 100 * sigma / y_rgb << "%)");
    CAPTURE(i);
    CHECK(rel(y_ss_spec, y_ss_rgb) < 0.07);  // measured 1.8-4.5%
    CHECK(std::abs(y_spec - y_rgb) <= 3.0 * sigma + 0.07 * y_rgb);
  }

  // Twilight: sun 5 deg below the horizon, sky towards the sun 5 deg above the horizon (higher up, the
  // paths' colour noise at 64 per pixel is too large for a fixed margin).
  const ReferenceView dusk = view_at(m, 1.0, 95.0, directions({5.0}, 0.0));
  const ReferenceImage dusk_rgb = render(m, dusk, rgb_sampling(), 64, true, true, 2);
  const ReferenceImage dusk_spec = render(m, dusk, reference_sampling(), 64, true, true, 2);
  for (size_t i = 0; i < dusk.directions.size(); ++i) {
    const glm::vec3 a = dusk_rgb.radiance[i], b = dusk_spec.radiance[i];
    const double rg_rgb = a.r / a.g, rg_spec = b.r / b.g;
    MESSAGE("sun zenith 95 deg, elevation 5 deg: r/g RGB " << rg_rgb << ", spectral "
                                            << rg_spec << " (RGB / spectral - 1: " << 100 * (rg_rgb / rg_spec - 1.0)
                                            << "%)");
    CAPTURE(i);
    CHECK(rg_rgb / rg_spec - 1.0 > 0.5);  // measured: +118% (the RGB model's twilight is far too red)
  }
}

TEST_CASE("spectral reference: 1 and 2 threads give identical bits") {
  const AtmosphereModel m = atmosphere_preset("reference");
  std::vector<double> el;
  for (int k = 0; k < 130; ++k) el.push_back(-10.0 + 100.0 * k / 129.0);  // three chunks of 64
  const ReferenceView v = view_at(m, 1000.0, 85.0, directions(el, 45.0));
  const ReferenceImage one = render(m, v, reference_sampling(), 4, true, true, 1);
  const ReferenceImage two = render(m, v, reference_sampling(), 4, true, true, 2);
  REQUIRE(one.radiance.size() == two.radiance.size());
  CHECK(std::memcmp(one.radiance.data(), two.radiance.data(), one.radiance.size() * sizeof(glm::vec3)) == 0);
  CHECK(std::memcmp(one.noise.data(), two.noise.data(), one.noise.size() * sizeof(float)) == 0);
}

TEST_CASE("spectral reference: its colour-ratio noise predicts the scatter between two seeds") {
  const AtmosphereModel m = atmosphere_preset("earth-clear");
  std::vector<glm::vec3> dirs;
  for (double az : {0.0, 60.0, 120.0, 180.0}) {
    const std::vector<glm::vec3> d = directions({2.0, 10.0, 30.0, 60.0}, az);
    dirs.insert(dirs.end(), d.begin(), d.end());
  }
  const ReferenceView v = view_at(m, 1.0, 60.0, dirs);
  ReferenceSettings s;
  s.sampling = reference_sampling();
  s.samples_per_pixel = 96;
  s.single_scattering = false;  // the paths alone: all of the noise, none of the deterministic light
  JobSystem jobs(2);
  const ReferenceImage a = render_reference(m, v, s, jobs, {});
  s.seed = 2;
  const ReferenceImage b = render_reference(m, v, s, jobs, {});
  // Per pixel, (ratio_a / ratio_b - 1)^2 estimates noise_a^2 + noise_b^2; compared over the pixels.
  glm::dvec2 scatter(0.0), predicted(0.0);
  for (size_t i = 0; i < dirs.size(); ++i) {
    const glm::vec3 x = a.radiance[i], y = b.radiance[i];
    const glm::dvec2 d((x.r / x.g) / (y.r / y.g) - 1.0, (x.b / x.g) / (y.b / y.g) - 1.0);
    scatter += d * d;
    predicted += glm::dvec2(a.ratio_noise[i] * a.ratio_noise[i] + b.ratio_noise[i] * b.ratio_noise[i]);
  }
  const glm::dvec2 ratio = glm::sqrt(scatter / predicted);
  MESSAGE("measured / predicted ratio scatter: r/g " << ratio.x << ", b/g " << ratio.y << " (predicted RMS r/g "
                                                    << 100 * std::sqrt(predicted.x / double(dirs.size())) << "%)");
  CHECK(ratio.x > 0.6);
  CHECK(ratio.x < 1.6);
  CHECK(ratio.y > 0.6);
  CHECK(ratio.y < 1.6);
}

// The mobile profile's q15 LUTs (engine/core/q15_scale.h) and the fixed-point
// composite: rounding, scales, what fixed point costs against float on the
// same LUTs, and the cases where fixed point fails (underflow, night, a very
// bright sun) handled without wrap-around.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "engine/core/q15_scale.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere_test_util.h"
#include "engine/core/job_system.h"
#include "engine/core/luminance.h"

using namespace cr;
using namespace cr::test;

namespace {

AtmosphereSettings q15_settings(bool fixed_composite) {
  AtmosphereSettings s = small_settings();
  s.full_schedule = true;
  s.lut_precision = LutPrecision::Q15;
  s.composite_precision = fixed_composite ? CompositePrecision::Fixed : CompositePrecision::Float;
  return s;
}

bool on_grid(float v, const Q15Scale& s) { return from_q15(to_q15(v, s), s) == v; }

}  // namespace

TEST_CASE("q15 scales and rounding: the largest value at code 32767, half a code of error, no wrap") {
  const Q15Scale s = q15_scale_for(1234.5f);
  CHECK(to_q15(1234.5f, s) == 32767);
  CHECK(to_q15(0.0f, s) == 0);
  CHECK(to_q15(1e30f, s) == 32767);  // saturates
  CHECK(to_q15(-5.0f, s) == 0);
  CHECK(to_q15(std::numeric_limits<float>::quiet_NaN(), s) == 0);
  for (int i = 0; i <= 100000; ++i) {
    const float v = 1234.5f * float(i) / 100000.0f;
    const float r = from_q15(to_q15(v, s), s);
    CHECK(std::abs(r - v) <= 0.5f * s.code_value() + 2.4e-7f * v);  // half a code, and float rounding
    CHECK(on_grid(r, s));  // rounding again changes nothing
  }
  const float values[] = {3.0f, std::numeric_limits<float>::infinity(), -1.0f,
                          std::numeric_limits<float>::quiet_NaN(), 7.0f};
  CHECK(max_value(values, 5, 1) == 7.0f);
  CHECK(q15_scale_for(0.0f).scale == 1.0f);  // an all-zero LUT
}

TEST_CASE("q15 LUTs: published LUTs lie on their q15 grid, and the fixed-point sky-view sample is the float one within 1.5 codes") {
  JobSystem jobs(1);
  LutScheduler s(q15_settings(true));
  const Camera cam = camera_at(2.0);
  run_frame(s, 0, cam, sun_from_zenith(80.0), jobs);
  const SkyViewLut& sv = *s.skyview();
  REQUIRE(sv.quantized());
  for (const glm::vec3& t : sv.image().texels)
    for (int c = 0; c < 3; ++c) CHECK(on_grid(t[c], sv.rest_scale()));
  const AerialPerspectiveLut& ap = *s.aerial_perspective();
  REQUIRE(ap.quantized());
  for (const glm::vec3& t : ap.transmittance().texels)
    for (int c = 0; c < 3; ++c) {
      CHECK(on_grid(t[c], Q15Scale{}));
      CHECK(t[c] <= 32767.0f / 32768.0f);
    }
  for (const glm::vec3& t : s.transmittance()->image().texels)
    for (int c = 0; c < 3; ++c) CHECK(on_grid(t[c], Q15Scale{}));
  // Two lerps then one: each rounds by at most half a code.
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i) {
      const glm::vec2 unit(float(i) / 40.0f * 0.997f, float(j) / 40.0f * 0.993f);
      const glm::vec3 a = sv.sample(unit, 0.0f), b = sv.sample_fixed(unit, 0.0f);
      for (int c = 0; c < 3; ++c) CHECK(std::abs(a[c] - b[c]) <= 1.5f * sv.rest_scale().code_value() * 1.001f);
      const glm::vec3 am = sv.sample(unit, 1.0f) - a, bm = sv.sample_fixed(unit, 1.0f) - b;
      for (int c = 0; c < 3; ++c) CHECK(std::abs(am[c] - bm[c]) <= 1.5f * sv.mie_scale().code_value() * 1.01f);
    }
}

TEST_CASE("fixed-point composite against the float composite on the same q15 LUTs, day to night") {
  JobSystem jobs(1);
  const Camera cam = Camera::look_at(glm::dvec3(0.0, 2.0, 0.0), glm::dvec3(1000.0, 60.0, 20.0), 1.0471976f,
                                     16.0f / 9.0f, 0.1f);
  const int w = 160, h = 90;
  // 45 deg, sunset, dusk (the twilight gradient), night.
  for (double zenith : {45.0, 89.0, 94.0, 110.0}) {
    CAPTURE(zenith);
    std::vector<glm::vec3> out[2];
    for (int k = 0; k < 2; ++k) {
      LutScheduler s(q15_settings(k == 1));
      const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(zenith), jobs);
      const SkyFrame f = frame_of(s, p, cam);
      REQUIRE(f.fixed == (k == 1));
      FrameBuffers b;
      b.resize(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (y > h / 2) {  // the lower half: ground at 300 m to 6 km
            const size_t i = b.index(x, y);
            b.depth[i] = 0.5f;
            b.distance[i] = 300.0f * float(1 + x % 20);
            b.color[i] = glm::vec3(2.0f, 1.5f, 1.0f) * float(1 + y % 3);
          }
      composite_sky(f, b, 0, 0, w, h);
      out[k] = b.color;
    }
    double peak = 0.0;
    for (const glm::vec3& c : out[0]) peak = std::max(peak, double(luminance(c)));
    REQUIRE(peak > 0.0);
    double worst = 0.0, mean = 0.0;
    for (size_t i = 0; i < out[0].size(); ++i) {
      CHECK(std::isfinite(luminance(out[1][i])));
      const double a = luminance(out[0][i]), b = luminance(out[1][i]);
      // Relative to the pixel, or to 1% of the frame's peak for pixels darker than that.
      const double e = std::abs(a - b) / std::max(a, 0.01 * peak);
      worst = std::max(worst, e);
      mean += e / double(out[0].size());
    }
    MESSAGE("sun zenith " << zenith << ": fixed vs float composite on q15 LUTs, mean " << mean << ", worst " << worst);
    // The lerps' rounding: a few codes of the LUT's brightest texel (these
    // small test LUTs are coarse: the largest steps between texels).
    CHECK(mean < 5e-4);
    CHECK(worst < 5e-3);
  }
}

TEST_CASE("where fixed point fails: transmittance underflows to 0, never below, and a very bright sun saturates nothing") {
  JobSystem jobs(1);
  AtmosphereModel dense;
  dense.rayleigh_scattering *= 100.0f;
  dense.mie_scattering *= 100.0f;
  dense.mie_absorption *= 100.0f;
  LutScheduler s(q15_settings(true));
  s.set_model(dense);
  const Camera cam = camera_at(2.0);
  const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(60.0), jobs);
  int underflow = 0;
  for (const glm::vec3& t : s.transmittance()->image().texels)
    for (int c = 0; c < 3; ++c) {
      CHECK(t[c] >= 0.0f);
      CHECK(t[c] <= 1.0f);
      underflow += t[c] == 0.0f;
    }
  MESSAGE("dense air: " << underflow << " transmittance texel channels under 2^-16 are 0");
  CHECK(underflow > 0);  // the failure exists here, and is a clean 0
  // The LUTs hold luminance for unit illuminance: a sun 10^4 x brighter scales the decoded result, not the codes.
  SkyFrame f = frame_of(s, p, cam);
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 0.2f, 0.3f));
  const glm::vec3 base = sky_radiance(f, dir, false);
  f.sun_illuminance *= 1e4f;
  const glm::vec3 bright = sky_radiance(f, dir, false);
  for (int c = 0; c < 3; ++c) {
    CHECK(std::isfinite(bright[c]));
    CHECK(bright[c] == doctest::Approx(base[c] * 1e4f).epsilon(1e-5));
  }
}

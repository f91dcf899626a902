#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "engine/shading/tonemap.h"

using namespace cr;

TEST_CASE("tonemap: exposure from EV100") {
  CHECK(exposure_scale(0.0f) == doctest::Approx(1.0f / 1.2f));
  CHECK(exposure_scale(15.0f) == doctest::Approx(1.0f / (1.2f * 32768.0f)));
  CHECK(exposure_scale(-2.0f) == doctest::Approx(4.0f / 1.2f));
}

TEST_CASE("tonemap: ACES fit is monotone, 0 -> 0, saturates at 1") {
  CHECK(tonemap_aces(0.0f) == 0.0f);
  CHECK(tonemap_aces(-1.0f) == 0.0f);
  CHECK(tonemap_aces(std::numeric_limits<float>::quiet_NaN()) == 0.0f);
  CHECK(tonemap_aces(std::numeric_limits<float>::infinity()) == 1.0f);
  CHECK(tonemap_aces(1e30f) == 1.0f);
  CHECK(tonemap_aces(1.0f) == doctest::Approx(0.8038f).epsilon(1e-3));
  float previous = 0.0f;
  for (int i = 1; i <= 20000; ++i) {
    const float x = float(i) * 1e-3f;
    const float y = tonemap_aces(x);
    CHECK(y >= previous);
    CHECK(y <= 1.0f);
    previous = y;
  }
}

TEST_CASE("tonemap: resolve to sRGB 8-bit is monotone, rounds, and maps 0 to 0") {
  CHECK(quantize_unorm8(0.0f) == 0);
  CHECK(quantize_unorm8(1.0f) == 255);
  CHECK(quantize_unorm8(0.5f / 255.0f) == 1);          // rounds half up
  CHECK(quantize_unorm8(0.49f / 255.0f) == 0);
  CHECK(quantize_unorm8(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(linear_to_srgb(0.0f) == 0.0f);
  CHECK(linear_to_srgb(1.0f) == doctest::Approx(1.0f));

  // A luminance ramp over 30 stops around the exposure point.
  const float ev100 = 12.0f;
  std::vector<glm::vec3> hdr;
  hdr.push_back(glm::vec3(0.0f));
  for (int i = 0; i < 3000; ++i) hdr.push_back(glm::vec3(1.2f * std::exp2(ev100 - 15.0f + float(i) * 0.01f)));
  std::vector<uint8_t> rgb(hdr.size() * 3);
  resolve_to_srgb8(hdr.data(), hdr.size(), ev100, rgb.data());
  CHECK(rgb[0] == 0);
  CHECK(rgb[1] == 0);
  CHECK(rgb[2] == 0);
  for (size_t i = 1; i < hdr.size(); ++i) {
    CHECK(rgb[i * 3] >= rgb[(i - 1) * 3]);
    CHECK(rgb[i * 3] == rgb[i * 3 + 1]);
  }
  CHECK(rgb[rgb.size() - 3] == 255);
  // Mid grey: 18% of the saturation luminance lands near the middle of the range.
  uint8_t grey[3];
  resolve_pixel(glm::vec3(0.18f * 1.2f * std::exp2(ev100)), exposure_scale(ev100), grey);
  CHECK(int(grey[0]) > 80);
  CHECK(int(grey[0]) < 160);
  // Per pixel and over a buffer agree bit for bit.
  uint8_t one[3];
  resolve_pixel(hdr[1500], exposure_scale(ev100), one);
  CHECK(one[0] == rgb[1500 * 3]);
}

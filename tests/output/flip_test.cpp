#include <doctest/doctest.h>

#include <array>
#include <cmath>

#include "engine/core/error.h"
#include "engine/output/flip.h"
#include "engine/core/srgb.h"

namespace {

cr::ImageRGBf uniform(int width, int height, float r, float g, float b) {
  cr::ImageRGBf image(width, height);
  for (size_t i = 0; i < image.pixel_count(); ++i) {
    image.rgb[i * 3] = r;
    image.rgb[i * 3 + 1] = g;
    image.rgb[i * 3 + 2] = b;
  }
  return image;
}

cr::ImageRGBf checker(int width, int height, int cell) {
  cr::ImageRGBf image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float v = ((x / cell + y / cell) % 2) ? 0.8f : 0.1f;
      float* p = image.pixel(x, y);
      p[0] = v;
      p[1] = 0.5f * v;
      p[2] = 0.3f;
    }
  return image;
}

// Hunt-adjusted L*a*b* of a linear sRGB colour, straight from the definitions.
std::array<double, 3> hunt_lab(double r, double g, double b) {
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  const double fx = f(x / 0.95047), fy = f(y), fz = f(z / 1.08883);
  const double l = 116 * fy - 16;
  return {l, 0.01 * l * 500 * (fx - fy), 0.01 * l * 200 * (fy - fz)};
}

}  // namespace

TEST_CASE("FLIP of identical images is 0") {
  const cr::ImageRGBf image = checker(24, 16, 3);
  const std::vector<float> map = cr::flip_error_map(image, image);
  REQUIRE(map.size() == 24 * 16);
  for (float e : map) CHECK(e == 0.0f);
  CHECK(cr::mean_error(map) == 0.0);
}

TEST_CASE("FLIP of black against white matches the paper's colour formula") {
  // Uniform images: the CSF filters leave them unchanged and there are no
  // features, so FLIP = redistributed HyAB(white, black)^qc, HyAB = 100.
  const auto green = hunt_lab(0, 1, 0), blue = hunt_lab(0, 0, 1);
  const double cmax = std::pow(
      std::abs(green[0] - blue[0]) + std::hypot(green[1] - blue[1], green[2] - blue[2]), 0.7);
  const double colour = std::pow(100.0, 0.7);
  REQUIRE(colour > 0.4 * cmax);
  const double expected = 0.95 + (colour - 0.4 * cmax) / (0.6 * cmax) * 0.05;

  const std::vector<float> map =
      cr::flip_error_map(uniform(8, 8, 0, 0, 0), uniform(8, 8, 1, 1, 1));
  CHECK(cr::mean_error(map) == doctest::Approx(expected).epsilon(1e-3));
  CHECK(cr::mean_error(map) > 0.95);
}

TEST_CASE("FLIP is symmetric, bounded and grows with the difference") {
  const cr::ImageRGBf reference = checker(32, 32, 4);
  auto offset = [&](float d) {
    cr::ImageRGBf image = reference;
    for (float& v : image.rgb) v += d;
    return image;
  };
  const double small = cr::mean_error(cr::flip_error_map(reference, offset(0.01f)));
  const double large = cr::mean_error(cr::flip_error_map(reference, offset(0.1f)));
  CHECK(small > 0.0);
  CHECK(large > small);
  CHECK(cr::flip_error_map(reference, offset(0.1f)) == cr::flip_error_map(offset(0.1f), reference));
  for (float e : cr::flip_error_map(reference, uniform(32, 32, 1, 0, 1))) {
    CHECK(e >= 0.0f);
    CHECK(e <= 1.0f);
  }
}

TEST_CASE("FLIP's feature term sees a removed edge that colour filtering blurs away") {
  // A one-pixel dark line on grey: CSF filtering spreads it, so the colour
  // term alone is small; the edge/point detectors raise the error on the line.
  cr::ImageRGBf with_line = uniform(32, 32, 0.5f, 0.5f, 0.5f);
  for (int y = 0; y < 32; ++y) {
    float* p = with_line.pixel(16, y);
    p[0] = p[1] = p[2] = 0.0f;
  }
  const cr::ImageRGBf plain = uniform(32, 32, 0.5f, 0.5f, 0.5f);
  const std::vector<float> map = cr::flip_error_map(plain, with_line);
  CHECK(map[16 * 32 + 16] > 0.5f);   // on the line
  CHECK(map[16 * 32 + 2] < 0.05f);  // far from it
}

TEST_CASE("FLIP matches NVIDIA's reference implementation on a small pattern") {
  // Expected values from the reference LDR-FLIP (NVlabs/flip, python/flip_api.py)
  // run on the same two images, given as sRGB values.
  auto image = [](int r_x, int r_y) {
    cr::ImageRGBf srgb(12, 10);
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 12; ++x) {
        float* p = srgb.pixel(x, y);
        p[0] = static_cast<float>((x * r_x + y * r_y) % 11) / 10.0f;
        p[1] = static_cast<float>((x * 5 + y * 11) % 13) / 12.0f;
        p[2] = static_cast<float>((x + y) % 2) * 0.5f + 0.25f;
      }
    for (float& v : srgb.rgb) v = cr::srgb_to_linear(v);
    return srgb;
  };
  const cr::ImageRGBf reference = image(7, 3), test = image(3, 7);
  const std::vector<float> map = cr::flip_error_map(reference, test);
  CHECK(cr::mean_error(map) == doctest::Approx(0.156933457).epsilon(1e-5));
  CHECK(map[3 * 12 + 4] == doctest::Approx(0.0744938225).epsilon(1e-4));
  CHECK(map[0] == doctest::Approx(0.00157909734).epsilon(1e-3));
  CHECK(cr::mean_error(cr::flip_error_map(reference, test, 20.0)) ==
        doctest::Approx(0.511245515).epsilon(1e-5));
}

TEST_CASE("FLIP rejects images of different sizes") {
  CHECK_THROWS_AS(cr::flip_error_map(uniform(4, 4, 0, 0, 0), uniform(4, 5, 0, 0, 0)), cr::Error);
}

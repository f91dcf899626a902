// The render_scale upscale (engine/render/upscale.h): Catmull-Rom colour
// with the 2x2 clamp, nearest depth, determinism across thread counts.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "engine/render/upscale.h"

namespace {

struct Image {
  int width, height;
  std::vector<glm::vec3> rgb;
};

std::vector<glm::vec3> upscale(const Image& source, int width, int height, unsigned threads = 2) {
  cr::JobSystem jobs(threads);
  std::vector<glm::vec3> out;
  cr::Upscaler(source.width, source.height, width, height).color(source.rgb, out, jobs);
  REQUIRE(out.size() == size_t(width) * size_t(height));
  return out;
}

Image random_image(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> radiance(0.0f, 5000.0f);
  Image img{w, h, std::vector<glm::vec3>(size_t(w) * size_t(h))};
  for (glm::vec3& c : img.rgb) c = {radiance(rng), radiance(rng), radiance(rng)};
  return img;
}

// The source pixel at or left of an output pixel's centre along one axis
// (source centres at i + 0.5), and the one after it, both inside the image.
std::pair<int, int> bracket(int o, int source, int output) {
  const int i = int(std::floor((o + 0.5) * source / output - 0.5));
  return {std::clamp(i, 0, source - 1), std::clamp(i + 1, 0, source - 1)};
}

}  // namespace

TEST_CASE("upscale: a constant image stays exactly that constant, colour and depth") {
  for (const auto& [sw, sh, w, h] : {std::array{7, 5, 16, 11}, std::array{10, 10, 13, 17}, std::array{1, 1, 4, 3}}) {
    const glm::vec3 c(0.3f, 1733.25f, 1e-7f);
    const Image img{sw, sh, std::vector<glm::vec3>(size_t(sw) * size_t(sh), c)};
    for (const glm::vec3& v : upscale(img, w, h)) REQUIRE(v == c);
    cr::JobSystem jobs(2);
    std::vector<float> depth;
    cr::Upscaler(sw, sh, w, h).nearest(std::vector<float>(size_t(sw) * size_t(sh), 0.125f), depth, jobs);
    REQUIRE(depth.size() == size_t(w) * size_t(h));
    for (float d : depth) REQUIRE(d == 0.125f);
  }
}

TEST_CASE("upscale: a linear ramp in x is reproduced away from the borders (Catmull-Rom is exact on lines)") {
  // Value 3 i + 1 at source column i (per channel a different slope), the same on every row.
  const auto ramp = [](int sw, int sh) {
    Image img{sw, sh, std::vector<glm::vec3>(size_t(sw) * size_t(sh))};
    for (int y = 0; y < sh; ++y)
      for (int x = 0; x < sw; ++x) img.rgb[size_t(y) * size_t(sw) + size_t(x)] = {3.0f * x + 1.0f, 0.5f * x, 40.0f - x};
    return img;
  };
  const auto check = [&](int sw, int w, int h, bool exact) {
    const int sh = 4;
    const std::vector<glm::vec3> out = upscale(ramp(sw, sh), w, h);
    int checked = 0;
    for (int x = 0; x < w; ++x) {
      const double u = (x + 0.5) * sw / w - 0.5;  // in source columns
      if (std::floor(u) < 1 || std::floor(u) > sw - 3) continue;  // a tap clamped at the border
      ++checked;
      const glm::vec3 expected(float(3.0 * u + 1.0), float(0.5 * u), float(40.0 - u));
      for (int y = 0; y < h; ++y) {
        const glm::vec3 v = out[size_t(y) * size_t(w) + size_t(x)];
        CAPTURE(sw);
        CAPTURE(x);
        if (exact) {
          REQUIRE(v == expected);
        } else {
          for (int k = 0; k < 3; ++k) REQUIRE(v[k] == doctest::Approx(expected[k]).epsilon(1e-6));
        }
      }
    }
    CHECK(checked >= w / 2);
  };
  check(16, 32, 8, true);   // scale 0.5: fractions 1/4 and 3/4, every weight, product and sum exact in float
  check(12, 17, 9, false);  // odd ratios: exact up to the weights' float rounding
}

TEST_CASE("upscale: the clamp keeps every pixel within its 2x2 source neighbourhood: a step edge does not overshoot") {
  // A dark-bright step in x and y, zero on one side: unclamped Catmull-Rom
  // would undershoot below zero and overshoot above the bright side.
  const int sw = 12, sh = 10, w = 29, h = 23;
  Image step{sw, sh, std::vector<glm::vec3>(size_t(sw) * size_t(sh))};
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x)
      step.rgb[size_t(y) * size_t(sw) + size_t(x)] = x < sw / 2 ? glm::vec3(0.0f) : glm::vec3(y < sh / 2 ? 100.0f : 10.0f);
  int between = 0;
  for (const glm::vec3& v : upscale(step, w, h)) {
    REQUIRE(v.x >= 0.0f);
    REQUIRE(v.x <= 100.0f);
    between += v.x > 0.0f && v.x < 10.0f;
  }
  CHECK(between > 0);  // the filter blends across the edge (it is not nearest-neighbour)

  const Image img = random_image(sw, sh, 7);
  const std::vector<glm::vec3> out = upscale(img, w, h);
  int clamped = 0;
  for (int y = 0; y < h; ++y) {
    const auto [y0, y1] = bracket(y, sh, h);
    for (int x = 0; x < w; ++x) {
      const auto [x0, x1] = bracket(x, sw, w);
      const auto at = [&](int i, int j) { return img.rgb[size_t(j) * size_t(sw) + size_t(i)]; };
      const glm::vec3 lo = glm::min(glm::min(at(x0, y0), at(x1, y0)), glm::min(at(x0, y1), at(x1, y1)));
      const glm::vec3 hi = glm::max(glm::max(at(x0, y0), at(x1, y0)), glm::max(at(x0, y1), at(x1, y1)));
      const glm::vec3 v = out[size_t(y) * size_t(w) + size_t(x)];
      for (int k = 0; k < 3; ++k) {
        REQUIRE(v[k] >= lo[k]);
        REQUIRE(v[k] <= hi[k]);
        clamped += v[k] == lo[k] || v[k] == hi[k];
      }
    }
  }
  CHECK(clamped > 0);  // noise rings: some channels were clamped
}

TEST_CASE("upscale: colour and nearest depth are bit-identical for 1, 2 and 5 threads, depth is a source sample") {
  const Image img = random_image(91, 53, 11);
  const int w = 182, h = 107;
  const std::vector<glm::vec3> one = upscale(img, w, h, 1);
  for (unsigned t : {2u, 5u}) {
    const std::vector<glm::vec3> many = upscale(img, w, h, t);
    CHECK(std::memcmp(one.data(), many.data(), one.size() * sizeof(glm::vec3)) == 0);
  }
  std::vector<float> depth(size_t(img.width) * size_t(img.height));
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = float(i);  // each sample names its pixel
  std::vector<float> d1, d5;
  cr::JobSystem jobs1(1), jobs5(5);
  const cr::Upscaler up(img.width, img.height, w, h);
  up.nearest(depth, d1, jobs1);
  up.nearest(depth, d5, jobs5);
  CHECK(d1 == d5);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // The source pixel under the output pixel's centre.
      const int sx = int((x + 0.5) * img.width / w), sy = int((y + 0.5) * img.height / h);
      REQUIRE(d1[size_t(y) * size_t(w) + size_t(x)] == float(sy * img.width + sx));
    }
}

TEST_CASE("upscale: through the reversible tonemap a sun-bright pixel does not spill its radiance over its neighbours") {
  // A sky of 1 with one pixel 10^6 brighter (the sun's disk against the sky, exposed).
  Image img{16, 16, std::vector<glm::vec3>(256, glm::vec3(1.0f))};
  img.rgb[8 * 16 + 8] = glm::vec3(1e6f);
  const int w = 21, h = 21;  // a non-integer ratio: every output pixel between source centres
  cr::JobSystem jobs(2);
  std::vector<glm::vec3> linear, tonemapped;
  const cr::Upscaler up(img.width, img.height, w, h);
  up.color(img.rgb, linear, jobs, 0.0f);
  up.color(img.rgb, tonemapped, jobs, 1.0f);
  double spill_linear = 0.0, spill_tonemapped = 0.0;
  int untouched = 0;
  for (size_t i = 0; i < linear.size(); ++i) {
    spill_linear += linear[i].g - 1.0;
    spill_tonemapped += tonemapped[i].g - 1.0;
    CHECK(tonemapped[i].g >= 1.0f - 1e-6f);  // the clamp still holds: nothing below the sky
    CHECK(tonemapped[i].g <= 1e6f);
    untouched += std::abs(tonemapped[i].g - 1.0f) <= 1e-6f;
  }
  // Linear filtering spreads on the order of the spike's energy; the tonemapped filter a few sky units.
  CHECK(spill_linear > 1e5);
  CHECK(spill_tonemapped < 1e-3 * spill_linear);
  // Pixels away from the spike come back as the sky they were (to float rounding).
  CHECK(untouched > w * h - 16);
}

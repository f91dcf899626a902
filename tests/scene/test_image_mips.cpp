// Mip chains: level sizes for any image size, and sRGB-correct averaging.
#include <doctest/doctest.h>

#include "engine/scene/image_mips.h"

namespace {

cr::Image make_image(int w, int h, bool srgb, uint8_t value = 0) {
  cr::Image img;
  img.srgb = srgb;
  img.mips.push_back({w, h, std::vector<uint8_t>(static_cast<size_t>(w) * h * 4, value)});
  return img;
}

}  // namespace

TEST_CASE("mip chains halve with floor down to 1x1, for non-power-of-two sizes too") {
  struct SizeCase {
    int w, h;
    std::vector<std::pair<int, int>> levels;
  };
  for (const SizeCase& c : std::vector<SizeCase>{{8, 4, {{8, 4}, {4, 2}, {2, 1}, {1, 1}}},
                                                 {5, 3, {{5, 3}, {2, 1}, {1, 1}}},
                                                 {1, 7, {{1, 7}, {1, 3}, {1, 1}}},
                                                 {1, 1, {{1, 1}}}}) {
    CAPTURE(c.w);
    CAPTURE(c.h);
    cr::Image img = make_image(c.w, c.h, false, 77);
    cr::generate_mips(img);
    REQUIRE(img.mips.size() == c.levels.size());
    for (size_t i = 0; i < c.levels.size(); ++i) {
      CHECK(img.mips[i].width == c.levels[i].first);
      CHECK(img.mips[i].height == c.levels[i].second);
      CHECK(img.mips[i].rgba.size() == static_cast<size_t>(c.levels[i].first * c.levels[i].second * 4));
      for (uint8_t v : img.mips[i].rgba) CHECK(v == 77);  // a constant image stays constant
    }
  }
}

TEST_CASE("sRGB images are averaged in linear light, linear images and alpha directly") {
  // 2x2 black/white checker with alpha 0/255.
  for (bool srgb : {true, false}) {
    CAPTURE(srgb);
    cr::Image img = make_image(2, 2, srgb);
    std::vector<uint8_t>& px = img.mips[0].rgba;
    for (int i : {0, 3}) {
      for (int c = 0; c < 4; ++c) px[i * 4 + c] = 255;
    }
    cr::generate_mips(img);
    REQUIRE(img.mips.size() == 2);
    const std::vector<uint8_t>& top = img.mips[1].rgba;
    for (int c = 0; c < 3; ++c) {
      if (srgb) {
        // Linear 0.5 encodes to 0.7354 * 255 = 187.5; never the naive 128.
        CHECK(top[c] >= 187);
        CHECK(top[c] <= 188);
      } else {
        CHECK(top[c] == 128);
      }
    }
    CHECK(top[3] == 128);  // alpha is linear in both
  }
}

TEST_CASE("odd edges fold the last row/column into the box") {
  // 3x1: values 0, 0, 255 -> one texel averaging all three (85), not just the first two.
  cr::Image img = make_image(3, 1, false);
  for (int c = 0; c < 4; ++c) img.mips[0].rgba[2 * 4 + c] = 255;
  cr::generate_mips(img);
  REQUIRE(img.mips.size() == 2);
  CHECK(img.mips[1].rgba[0] == 85);
}

TEST_CASE("a chain that drops its top levels keeps exactly the full chain's lower levels") {
  cr::Image full = make_image(13, 6, true);
  for (size_t i = 0; i < full.mips[0].rgba.size(); ++i) full.mips[0].rgba[i] = uint8_t((i * 71 + 5) % 256);
  const cr::Image base = full;
  cr::generate_mips(full);
  REQUIRE(full.mips.size() == 4);  // 13x6, 6x3, 3x1, 1x1
  for (int drop = 1; drop <= 5; ++drop) {
    CAPTURE(drop);
    cr::Image img = base;
    cr::generate_mips(img, drop);
    const size_t first = std::min<size_t>(size_t(drop), full.mips.size() - 1);  // never past 1x1
    REQUIRE(img.mips.size() == full.mips.size() - first);
    for (size_t l = 0; l < img.mips.size(); ++l) {
      CHECK(img.mips[l].width == full.mips[first + l].width);
      CHECK(img.mips[l].height == full.mips[first + l].height);
      CHECK(img.mips[l].rgba == full.mips[first + l].rgba);
    }
  }
}

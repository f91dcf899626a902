#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "engine/shading/srgb.h"
#include "engine/shading/texture_sampler.h"

using namespace cr;

namespace {

// A linear image whose every texel of level l has red = 40 * l (a level's
// identity survives any filtering within the level).
Image level_coded_image(int size) {
  Image img;
  for (int l = 0, s = size; s >= 1; ++l, s /= 2) {
    MipLevel m;
    m.width = m.height = s;
    m.rgba.assign(size_t(s) * s * 4, 255);
    for (size_t i = 0; i < size_t(s) * s; ++i) m.rgba[i * 4] = uint8_t(40 * l);
    img.mips.push_back(m);
  }
  return img;
}

// A 5x1 linear image with red = 10, 20, 30, 40, 50 from left to right (odd,
// so that u = -0.25 and 1.25 fall inside texels, not on their borders).
Image row_image() {
  Image img;
  MipLevel m;
  m.width = 5;
  m.height = 1;
  m.rgba.assign(5 * 4, 0);
  for (size_t i = 0; i < 5; ++i) {
    m.rgba[i * 4] = uint8_t(10 * (i + 1));
    m.rgba[i * 4 + 3] = 255;
  }
  img.mips.push_back(m);
  return img;
}

float red(const glm::vec4& c) { return c.r * 255.0f; }

Sampler make_sampler(Filter mag, Filter min, std::optional<Filter> mip, Wrap wrap = Wrap::Repeat) {
  Sampler s;
  s.mag = mag;
  s.min = min;
  s.mip = mip;
  s.wrap_s = s.wrap_t = wrap;
  return s;
}

}  // namespace

TEST_CASE("texture LOD follows the scale-factor rule and picks the expected level") {
  const Image img = level_coded_image(64);  // 7 levels
  const glm::vec2 zero(0.0f);
  // 4 texels per pixel along x: lambda = log2(4) = 2.
  CHECK(texture_lod(img, {4.0f / 64.0f, 0.0f}, zero) == doctest::Approx(2.0f));
  // Anisotropic footprint: the longer axis (8 texels) decides.
  CHECK(texture_lod(img, {2.0f / 64.0f, 0.0f}, {0.0f, 8.0f / 64.0f}) == doctest::Approx(3.0f));
  CHECK(texture_lod(img, {3.0f / 64.0f, 4.0f / 64.0f}, zero) == doctest::Approx(std::log2(5.0f)));

  const Sampler nearest_mip = make_sampler(Filter::Linear, Filter::Linear, Filter::Nearest);
  const Sampler linear_mip = make_sampler(Filter::Linear, Filter::Linear, Filter::Linear);
  const glm::vec2 uv(0.3f, 0.7f);
  CHECK(red(sample_texture(img, nearest_mip, uv, {4.0f / 64.0f, 0.0f}, zero)) == doctest::Approx(80.0f));
  CHECK(red(sample_texture(img, linear_mip, uv, {4.0f / 64.0f, 0.0f}, zero)) == doctest::Approx(80.0f));
  CHECK(red(sample_texture(img, linear_mip, uv, {2.0f / 64.0f, 0.0f}, {0.0f, 8.0f / 64.0f})) == doctest::Approx(120.0f));
  // Nearest mip: OpenGL's d = ceil(lambda + 1/2) - 1.
  CHECK(red(sample_texture(img, nearest_mip, uv, {std::exp2(2.4f) / 64.0f, 0.0f}, zero)) == doctest::Approx(80.0f));
  CHECK(red(sample_texture(img, nearest_mip, uv, {std::exp2(2.6f) / 64.0f, 0.0f}, zero)) == doctest::Approx(120.0f));
  // Magnification (and zero derivatives) read level 0.
  CHECK(red(sample_texture(img, linear_mip, uv, {0.25f / 64.0f, 0.0f}, zero)) == doctest::Approx(0.0f));
  CHECK(red(sample_texture(img, linear_mip, uv, zero, zero)) == doctest::Approx(0.0f));
  // Without mipmapping minification stays on level 0.
  CHECK(red(sample_texture(img, make_sampler(Filter::Linear, Filter::Linear, std::nullopt), uv,
                           {16.0f / 64.0f, 0.0f}, zero)) == doctest::Approx(0.0f));
  // LOD is clamped to the chain: the 1x1 level is the last.
  CHECK(red(sample_texture(img, linear_mip, uv, {1e6f, 0.0f}, zero)) == doctest::Approx(240.0f));
  CHECK(red(sample_texture(img, nearest_mip, uv, {std::numeric_limits<float>::infinity(), 0.0f}, zero)) ==
        doctest::Approx(240.0f));
}

TEST_CASE("trilinear filtering blends adjacent levels by the LOD fraction") {
  const Image img = level_coded_image(64);
  const Sampler s = make_sampler(Filter::Linear, Filter::Linear, Filter::Linear);
  for (float lambda : {1.25f, 2.5f, 3.75f}) {
    const float expected = 40.0f * lambda;  // levels floor and floor+1, mixed by the fraction
    CHECK(red(sample_texture(img, s, {0.5f, 0.5f}, {std::exp2(lambda) / 64.0f, 0.0f}, {0.0f, 0.0f})) ==
          doctest::Approx(expected).epsilon(1e-4));
  }
}

TEST_CASE("wrap modes at coordinates outside [0, 1]") {
  const Image img = row_image();
  const Filter n = Filter::Nearest;
  auto at = [&](float u, Wrap wrap, Filter f) { return red(sample_level(img, 0, {u, 0.5f}, f, wrap, wrap)); };
  // u = -0.25 (texel coordinate -1.25): repeat -> 3.75 (texel 3), clamp ->
  // texel 0, mirror -> 1.25 (texel 1).
  CHECK(at(-0.25f, Wrap::Repeat, n) == doctest::Approx(40.0f));
  CHECK(at(-0.25f, Wrap::ClampToEdge, n) == doctest::Approx(10.0f));
  CHECK(at(-0.25f, Wrap::MirroredRepeat, n) == doctest::Approx(20.0f));
  // u = 1.25 (6.25): repeat -> 1.25 (texel 1), clamp -> texel 4, mirror -> 3.75 (texel 3).
  CHECK(at(1.25f, Wrap::Repeat, n) == doctest::Approx(20.0f));
  CHECK(at(1.25f, Wrap::ClampToEdge, n) == doctest::Approx(50.0f));
  CHECK(at(1.25f, Wrap::MirroredRepeat, n) == doctest::Approx(40.0f));
  // The mirrored period is 2: u = -1.25 reads like 0.75 (3.75, texel 3), 2.25 like 0.25.
  CHECK(at(-1.25f, Wrap::MirroredRepeat, n) == doctest::Approx(40.0f));
  CHECK(at(2.25f, Wrap::MirroredRepeat, n) == doctest::Approx(20.0f));
  // Linear at the left edge (u = 0) blends with the wrapped neighbour.
  const Filter l = Filter::Linear;
  CHECK(at(0.0f, Wrap::Repeat, l) == doctest::Approx(30.0f));  // (texel 4 + texel 0) / 2
  CHECK(at(0.0f, Wrap::ClampToEdge, l) == doctest::Approx(10.0f));
  CHECK(at(0.0f, Wrap::MirroredRepeat, l) == doctest::Approx(10.0f));
  CHECK(at(1.0f, Wrap::Repeat, l) == doctest::Approx(30.0f));
  CHECK(at(1.0f, Wrap::ClampToEdge, l) == doctest::Approx(50.0f));
  // Huge and non-finite coordinates stay finite and in range.
  for (float u : {1e30f, -1e30f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    for (Wrap w : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
      const float v = at(u, w, l);
      CHECK(v >= 10.0f);
      CHECK(v <= 50.0f);
    }
  }
}

TEST_CASE("nearest and linear filters within a level") {
  const Image img = row_image();
  // u = 0.26 -> texel coordinate 1.3: nearest texel 1; linear 0.8 of the way from texel 0 to 1.
  CHECK(red(sample_level(img, 0, {0.26f, 0.5f}, Filter::Nearest, Wrap::Repeat, Wrap::Repeat)) == doctest::Approx(20.0f));
  CHECK(red(sample_level(img, 0, {0.26f, 0.5f}, Filter::Linear, Wrap::Repeat, Wrap::Repeat)) == doctest::Approx(18.0f));
  // At a texel centre both agree.
  CHECK(red(sample_level(img, 0, {0.5f, 0.5f}, Filter::Linear, Wrap::Repeat, Wrap::Repeat)) == doctest::Approx(30.0f));
  // Magnification uses the mag filter, minification the min filter.
  const Sampler s = make_sampler(Filter::Nearest, Filter::Linear, std::nullopt);
  CHECK(red(sample_texture(img, s, {0.26f, 0.5f}, {0.0f, 0.0f}, {0.0f, 0.0f})) == doctest::Approx(20.0f));
  CHECK(red(sample_texture(img, s, {0.26f, 0.5f}, {1.0f, 0.0f}, {0.0f, 0.0f})) == doctest::Approx(18.0f));
}

TEST_CASE("sRGB images decode through the table; the table round-trips every code") {
  const auto& table = srgb_decode_table();
  CHECK(table[0] == 0.0f);
  CHECK(table[255] == doctest::Approx(1.0f));
  CHECK(table[128] == doctest::Approx(0.2158605f).epsilon(1e-5));
  for (int v = 0; v < 256; ++v) {
    const float encoded = linear_to_srgb(table[size_t(v)]) * 255.0f;
    CHECK(int(std::floor(encoded + 0.5f)) == v);
    if (v > 0) CHECK(table[size_t(v)] > table[size_t(v - 1)]);
  }
  Image img;
  img.srgb = true;
  img.mips.push_back(MipLevel{1, 1, {128, 64, 255, 128}});
  const glm::vec4 c = sample_level(img, 0, {0.5f, 0.5f}, Filter::Linear, Wrap::Repeat, Wrap::Repeat);
  CHECK(c.r == table[128]);
  CHECK(c.g == table[64]);
  CHECK(c.b == table[255]);
  CHECK(c.a == doctest::Approx(128.0f / 255.0f));  // alpha is always linear
}

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "engine/shading/small_floor.h"
#include "engine/core/srgb.h"
#include "engine/shading/texel_decode.h"
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

// A size x size sRGB mip chain of arbitrary bytes (byte i of a level is
// (i * mul + add) % mod): distinct texels, every channel varying.
Image scrambled_image(int size, size_t mul, size_t add, size_t mod) {
  Image img = level_coded_image(size);
  for (MipLevel& m : img.mips)
    for (size_t i = 0; i < m.rgba.size(); ++i) m.rgba[i] = uint8_t((i * mul + add) % mod);
  img.srgb = true;
  return img;
}

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

TEST_CASE("floor_to_int equals std::floor on small finite values") {
  for (float x : {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 0.999999f, -0.999999f, 1e-30f, -1e-30f, 255.5f, -256.0f,
                  8388607.5f, -8388607.5f, 16777216.0f, -2147483520.0f}) {
    CHECK(floor_to_int(x) == int(std::floor(x)));
  }
}

// The OpenGL wrap formula for any integer index, as written in the specification.
int reference_wrap(int i, int n, Wrap wrap) {
  if (wrap == Wrap::ClampToEdge) return std::clamp(i, 0, n - 1);
  if (wrap == Wrap::Repeat) return ((i % n) + n) % n;
  const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
  return m < n ? m : 2 * n - 1 - m;
}

TEST_CASE("sample_level matches the specification's formulas bit for bit at and across the edges") {
  // Odd sizes and distinct texels, so that a wrong texel or weight shows.
  Image img;
  img.srgb = true;
  MipLevel m;
  m.width = 13;
  m.height = 7;
  for (int i = 0; i < 13 * 7 * 4; ++i) m.rgba.push_back(uint8_t((i * 37 + 11) % 256));
  img.mips.push_back(m);
  auto texel = [&](int x, int y) { return fetch_texel(img, 0, x, y); };
  for (Wrap wrap : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
    for (float u : {-3.96f, -1.0f, -0.5f, -0.01f, 0.0f, 0.02f, 0.3f, 0.5f, 0.97f, 1.0f, 1.04f, 2.5f, 7.31f}) {
      const float v = 1.0f - 0.9f * u;
      // Coordinates within the reduced ranges the sampler relies on.
      const float ru = wrap == Wrap::ClampToEdge ? std::clamp(u, -1.0f, 2.0f)
                       : wrap == Wrap::Repeat    ? u - std::floor(u)
                                                 : u - 2.0f * std::floor(0.5f * u);
      const float rv = wrap == Wrap::ClampToEdge ? std::clamp(v, -1.0f, 2.0f)
                       : wrap == Wrap::Repeat    ? v - std::floor(v)
                                                 : v - 2.0f * std::floor(0.5f * v);
      const float fx = ru * 13.0f - 0.5f, fy = rv * 7.0f - 0.5f;
      const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
      const float ax = fx - std::floor(fx), ay = fy - std::floor(fy);
      const int xa = reference_wrap(x0, 13, wrap), xb = reference_wrap(x0 + 1, 13, wrap);
      const int ya = reference_wrap(y0, 7, wrap), yb = reference_wrap(y0 + 1, 7, wrap);
      const glm::vec4 expected = glm::mix(glm::mix(texel(xa, ya), texel(xb, ya), ax),
                                          glm::mix(texel(xa, yb), texel(xb, yb), ax), ay);
      CHECK(sample_level(img, 0, {u, v}, Filter::Linear, wrap, wrap) == expected);
      const glm::vec4 nearest = texel(reference_wrap(int(std::floor(ru * 13.0f)), 13, wrap),
                                      reference_wrap(int(std::floor(rv * 7.0f)), 7, wrap));
      CHECK(sample_level(img, 0, {u, v}, Filter::Nearest, wrap, wrap) == nearest);
    }
  }
}

TEST_CASE("texture footprint: one footprint samples every image of its size as that image's own lookup") {
  // Two different images of one size: the footprint of the first, applied to
  // the second, must give exactly the second's own lookup, for every filter
  // and wrap mode and for magnified, in-chain and past-the-chain LODs.
  Image a = level_coded_image(16);
  const Image b = scrambled_image(16, 37, 11, 251);
  const Filter filters[2] = {Filter::Nearest, Filter::Linear};
  const Wrap wraps[3] = {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat};
  int compared = 0;
  for (Filter mag : filters)
    for (Filter min : filters)
      for (Filter mip : filters)
        for (Wrap wrap : wraps) {
          const Sampler sampler{wrap, wrap, mag, min, mip};
          for (float lambda : {-2.0f, 0.3f, 1.75f, 2.0f, 9.0f})
            for (glm::vec2 uv : {glm::vec2(0.37f, 0.81f), glm::vec2(-1.3f, 2.6f), glm::vec2(0.999f, 0.001f)}) {
              const TextureFootprint f = texture_footprint(a, sampler, uv, lambda);
              const glm::vec4 shared = sample_footprint(b, f);
              const glm::vec4 own = sample_texture_at_lod(b, sampler, uv, lambda);
              CHECK(shared == own);
              ++compared;
            }
        }
  CHECK(compared == 2 * 2 * 2 * 3 * 5 * 3);
  // An image without levels reads as opaque white through any footprint.
  CHECK(sample_footprint(Image{}, texture_footprint(a, Sampler{}, glm::vec2(0.5f), 0.0f)) == glm::vec4(1.0f));
}

TEST_CASE("sample_textures equals each image's own lookup, footprints shared or not") {
  // Images of two sizes through two samplers, in an order that switches both
  // (each switch recomputes what it invalidates), plus an image without levels.
  Image small = level_coded_image(16);
  Image large = level_coded_image(64);
  const Image other = scrambled_image(16, 53, 7, 251);
  const Image empty;
  const Sampler trilinear = make_sampler(Filter::Linear, Filter::Linear, Filter::Linear);
  const Sampler mirrored = make_sampler(Filter::Nearest, Filter::Linear, Filter::Nearest, Wrap::MirroredRepeat);
  const TextureLookup lookups[] = {{&small, &trilinear}, {&other, &trilinear}, {&other, &mirrored},
                                   {&large, &mirrored},  {&empty, &trilinear}, {&small, &trilinear}};
  constexpr int kCount = int(std::size(lookups));
  for (glm::vec2 uv : {glm::vec2(0.37f, 0.81f), glm::vec2(-1.3f, 2.6f)})
    for (float scale : {0.0f, 0.004f, 0.03f, 0.2f, 3.0f}) {
      const glm::vec2 dx(scale, 0.3f * scale), dy(-0.1f * scale, 0.7f * scale);
      glm::vec4 out[kCount];
      sample_textures(lookups, kCount, uv, dx, dy, out);
      for (int k = 0; k < kCount; ++k)
        CHECK(out[k] == sample_texture(*lookups[k].image, *lookups[k].sampler, uv, dx, dy));
    }
}

TEST_CASE("texels decode through the tables: sRGB colour, linear alpha and UNORM channels, every code") {
  // All 256 codes in every channel, for an sRGB and a linear image, read
  // texel by texel and through nearest and linear lookups at texel centres.
  for (bool srgb : {false, true}) {
    Image img;
    img.srgb = srgb;
    MipLevel m;
    m.width = 256;
    m.height = 1;
    for (int i = 0; i < 256; ++i)
      for (int c = 0; c < 4; ++c) m.rgba.push_back(uint8_t((i + 64 * c) % 256));
    img.mips.push_back(m);
    for (int i = 0; i < 256; ++i) {
      const glm::vec2 centre((float(i) + 0.5f) / 256.0f, 0.5f);
      const glm::vec4 texel = fetch_texel(img, 0, i, 0);
      const glm::vec4 nearest = sample_level(img, 0, centre, Filter::Nearest, Wrap::Repeat, Wrap::Repeat);
      const glm::vec4 linear = sample_level(img, 0, centre, Filter::Linear, Wrap::Repeat, Wrap::Repeat);
      for (int c = 0; c < 4; ++c) {
        const size_t code = size_t((i + 64 * c) % 256);
        const float expected = srgb && c < 3 ? srgb_decode_table()[code] : unorm_decode_table()[code];
        CHECK(texel[c] == expected);
        CHECK(nearest[c] == expected);
        CHECK(linear[c] == expected);
      }
    }
  }
  for (int code = 0; code < 256; ++code) CHECK(unorm_decode_table()[size_t(code)] == float(code) / 255.0f);
#if defined(__AVX2__)
  // Two linear texels decoded side by side: the same floats as one by one.
  for (int code = 0; code < 256; ++code) {
    const uint8_t a[4] = {uint8_t(code), uint8_t(255 - code), uint8_t(code * 7), uint8_t(code * 13)};
    const uint8_t b[4] = {uint8_t(code * 3), uint8_t(code + 1), uint8_t(code * 11), uint8_t(code * 5)};
    const LinearTexels::Pair pair = LinearTexels::pair(a, b);
    for (int c = 0; c < 4; ++c) {
      CHECK(pair[c] == unorm_decode_table()[a[c]]);
      CHECK(pair[4 + c] == unorm_decode_table()[b[c]]);
    }
  }
#endif
}

TEST_CASE("sample_textures over many points equals the lookups point by point, bit for bit") {
  // Lookups that switch image size and sampler (each switch recomputes what it
  // invalidates), an image without levels, sRGB and linear images; points
  // with zero, tiny, huge, infinite and NaN derivatives and UVs far outside
  // [0, 1], so that every mip branch runs.
  Image small = level_coded_image(16);
  const Image large = scrambled_image(64, 41, 5, 256);
  Image coded = large;
  coded.srgb = false;
  const Image empty;
  const Sampler trilinear = make_sampler(Filter::Linear, Filter::Linear, Filter::Linear);
  const Sampler mirrored = make_sampler(Filter::Nearest, Filter::Linear, Filter::Nearest, Wrap::MirroredRepeat);
  const Sampler clamped = make_sampler(Filter::Linear, Filter::Nearest, Filter::Linear, Wrap::ClampToEdge);
  const Sampler base_only = make_sampler(Filter::Linear, Filter::Nearest, std::nullopt);
  const TextureLookup lookups[] = {{&small, &trilinear}, {&small, &mirrored}, {&empty, &trilinear},
                                   {&large, &mirrored},  {&coded, &mirrored}, {&large, &clamped},
                                   {&small, &base_only}, {&coded, &trilinear}};
  constexpr int kCount = int(std::size(lookups));
  constexpr int kPoints = TexturePoints::kCapacity;
  float u[kPoints], v[kPoints], du_dx[kPoints], dv_dx[kPoints], du_dy[kPoints], dv_dy[kPoints];
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float scales[] = {0.0f, 1e-6f, 0.004f, 0.011f, 0.03f, 0.07f, 0.2f, 3.0f, 1e30f, inf, nan};
  for (int i = 0; i < kPoints; ++i) {
    const float s = scales[size_t(i) % std::size(scales)];
    u[i] = float(i) * 0.173f - 4.0f;
    v[i] = float(i * i % 61) * 0.0419f - 1.0f;
    du_dx[i] = s;
    dv_dx[i] = 0.3f * s;
    du_dy[i] = -0.1f * s * float(i % 3);
    dv_dy[i] = 0.7f * s * float(i % 5);
  }
  u[7] = inf;
  v[9] = nan;
  u[11] = 3e9f;
  for (int n : {kPoints, 37, 1}) {
    const TexturePoints points{n, u, v, du_dx, dv_dx, du_dy, dv_dy};
    glm::vec4 out[kCount * kPoints];
    sample_textures(lookups, kCount, points, out);
    int compared = 0;
    for (int i = 0; i < n; ++i) {
      glm::vec4 expected[kCount];
      sample_textures(lookups, kCount, {u[i], v[i]}, {du_dx[i], dv_dx[i]}, {du_dy[i], dv_dy[i]}, expected);
      for (int k = 0; k < kCount; ++k) {
        CHECK(std::memcmp(&out[k * n + i], &expected[k], sizeof(glm::vec4)) == 0);
        ++compared;
      }
    }
    CHECK(compared == n * kCount);
  }
}

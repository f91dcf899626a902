#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "engine/shading/texture_sampler.h"
#include "engine/shading/trilinear_footprints.h"

using namespace cr;

namespace {

// A full mip chain (each level half the last, rounded down, at least 1)
// with texels that differ from one another.
Image chain(int width, int height) {
  Image img;
  for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
    MipLevel m;
    m.width = w;
    m.height = h;
    m.rgba.resize(size_t(w) * size_t(h) * 4);
    for (size_t i = 0; i < m.rgba.size(); ++i) m.rgba[i] = uint8_t((i * 97 + img.mips.size() * 31 + 7) % 256);
    img.mips.push_back(m);
    if (w == 1 && h == 1) break;
  }
  return img;
}

Sampler trilinear_sampler(Wrap s, Wrap t) {
  Sampler sampler;
  sampler.wrap_s = s;
  sampler.wrap_t = t;
  sampler.mag = sampler.min = Filter::Linear;
  sampler.mip = Filter::Linear;
  return sampler;
}

// Coordinates and levels of detail that reach every branch: ordinary,
// negative and huge values, the 2^23 boundary, exact integers and texel
// borders, signed zeros, infinities and NaN; lambda at, between and past the
// levels (t == 0 included).
struct Points {
  std::vector<float> u, v, lambda;
};
Points edge_and_random_points(int levels, int count, uint32_t seed) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float coordinates[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 1.0f / 512.0f, -1e-30f, 1e-30f, 0.99999994f,
                               -0.99999994f, 2.0f, -2.0f, 2.5f, -1.5f, 3.7f, -123.456f, 8388607.5f, 8388608.0f,
                               -8388608.0f, 3e9f, -3e9f, 1e38f, inf, -inf, nan};
  const float last = float(levels - 1);
  const float lods[] = {-inf, -3.0f, 0.0f, -0.0f, 1e-7f, 0.5f, 1.0f, 1.25f, last - 0.5f, last, last + 1e-6f,
                        last + 3.0f, inf, nan};
  Points p;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> wide(-40.0f, 40.0f), unit(0.0f, 1.0f), lod(-2.0f, last + 2.0f);
  std::uniform_int_distribution<size_t> pick(0, 1000);
  for (int i = 0; i < count; ++i) {
    const size_t r = pick(rng);
    p.u.push_back(r % 4 == 0 ? coordinates[pick(rng) % std::size(coordinates)] : (r % 4 == 1 ? unit(rng) : wide(rng)));
    p.v.push_back(r % 5 == 0 ? coordinates[pick(rng) % std::size(coordinates)] : (r % 5 == 1 ? unit(rng) : wide(rng)));
    // Integers and halves too: t == 0 inside the chain.
    const float l = lod(rng);
    p.lambda.push_back(r % 3 == 0 ? lods[pick(rng) % std::size(lods)] : (r % 7 == 1 ? std::round(l * 2.0f) * 0.5f : l));
  }
  return p;
}

}  // namespace

TEST_CASE("trilinear footprints equal texture_footprint's levels, indices and weights bit for bit") {
  const Wrap wraps[] = {Wrap::Repeat, Wrap::ClampToEdge};
  int compared = 0;
  for (glm::ivec2 size : {glm::ivec2(256, 256), glm::ivec2(37, 5), glm::ivec2(1, 1), glm::ivec2(64, 16),
                          glm::ivec2(3, 100)}) {
    const Image img = chain(size.x, size.y);
    const Points p = edge_and_random_points(int(img.mips.size()), 2000, uint32_t(size.x * 131 + size.y));
    for (Wrap s : wraps)
      for (Wrap t : wraps) {
        const Sampler sampler = trilinear_sampler(s, t);
        REQUIRE(takes_trilinear_footprints(img, sampler));
        for (size_t begin = 0; begin < p.u.size(); begin += TrilinearFootprints::kCapacity) {
          const int n = int(std::min(p.u.size() - begin, size_t(TrilinearFootprints::kCapacity)));
          TrilinearFootprints f;
          trilinear_footprints(img, sampler, &p.u[begin], &p.v[begin], &p.lambda[begin], n, f);
          for (int i = 0; i < n; ++i) {
            const size_t j = begin + size_t(i);
            const TextureFootprint expected = texture_footprint(img, sampler, {p.u[j], p.v[j]}, p.lambda[j]);
            REQUIRE(expected.levels >= 1);
            CHECK(std::memcmp(&f.t[i], &expected.t, sizeof(float)) == 0);
            CHECK((f.t[i] != 0.0f) == (expected.levels == 2));
            for (int slot = 0; slot < expected.levels; ++slot) {
              const TextureFootprint::Level& e = expected.level[slot];
              CHECK(f.level[slot][i] == e.index);
              for (int c = 0; c < 4; ++c) CHECK(f.texel[slot][c][i] == e.texel[c]);
              CHECK(std::memcmp(&f.ax[slot][i], &e.ax, sizeof(float)) == 0);
              CHECK(std::memcmp(&f.ay[slot][i], &e.ay, sizeof(float)) == 0);
            }
            ++compared;
          }
        }
      }
  }
  CHECK(compared == 5 * 4 * 2000);
}

TEST_CASE("only linear/linear/linear-mip samplers with Repeat or ClampToEdge wraps on halving chains take the trilinear footprints") {
  const Image img = chain(37, 5);
  CHECK(takes_trilinear_footprints(img, trilinear_sampler(Wrap::Repeat, Wrap::ClampToEdge)));
  CHECK_FALSE(takes_trilinear_footprints(img, trilinear_sampler(Wrap::MirroredRepeat, Wrap::Repeat)));
  CHECK_FALSE(takes_trilinear_footprints(img, trilinear_sampler(Wrap::Repeat, Wrap::MirroredRepeat)));
  Sampler s = trilinear_sampler(Wrap::Repeat, Wrap::Repeat);
  s.mip = std::nullopt;
  CHECK_FALSE(takes_trilinear_footprints(img, s));
  s.mip = Filter::Nearest;
  CHECK_FALSE(takes_trilinear_footprints(img, s));
  s = trilinear_sampler(Wrap::Repeat, Wrap::Repeat);
  s.min = Filter::Nearest;
  CHECK_FALSE(takes_trilinear_footprints(img, s));
  s = trilinear_sampler(Wrap::Repeat, Wrap::Repeat);
  s.mag = Filter::Nearest;
  CHECK_FALSE(takes_trilinear_footprints(img, s));
  // Level sizes are computed from the base size: other chains take the general path.
  s = trilinear_sampler(Wrap::Repeat, Wrap::Repeat);
  CHECK_FALSE(takes_trilinear_footprints(Image{}, s));
  Image rounded_up = img;
  rounded_up.mips[1].width = 19;
  CHECK_FALSE(takes_trilinear_footprints(rounded_up, s));
  Image partial = img;
  partial.mips.resize(3);
  CHECK(takes_trilinear_footprints(partial, s));
}

TEST_CASE("batched trilinear lookups equal sample_texture bit for bit, in pairs and alone") {
  // sRGB and linear images of one size sharing the footprint, in pairs of
  // every colour-space combination (filtered together), and alone (one of
  // another size between them).
  Image base = chain(64, 64);
  base.srgb = true;
  const Image rough = chain(64, 64);
  const Image odd = chain(37, 5);
  const Sampler repeat = trilinear_sampler(Wrap::Repeat, Wrap::Repeat);
  const Sampler mixed = trilinear_sampler(Wrap::ClampToEdge, Wrap::Repeat);
  const TextureLookup lookups[] = {{&base, &repeat}, {&rough, &repeat}, {&rough, &repeat}, {&base, &repeat},
                                   {&base, &repeat}, {&base, &repeat},  {&rough, &repeat}, {&rough, &repeat},
                                   {&odd, &mixed},   {&base, &mixed},   {&rough, &mixed}};
  constexpr int kCount = int(std::size(lookups));
  constexpr int kPoints = TexturePoints::kCapacity;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uv(-3.0f, 3.0f);
  std::uniform_real_distribution<float> log_scale(-12.0f, 2.0f);
  int compared = 0;
  for (int batch = 0; batch < 40; ++batch) {
    float u[kPoints], v[kPoints], du_dx[kPoints], dv_dx[kPoints], du_dy[kPoints], dv_dy[kPoints];
    for (int i = 0; i < kPoints; ++i) {
      u[i] = uv(rng);
      v[i] = uv(rng);
      const float s = std::exp2(log_scale(rng));
      du_dx[i] = s * uv(rng);
      dv_dx[i] = s * uv(rng);
      du_dy[i] = s * uv(rng);
      dv_dy[i] = s * uv(rng);
    }
    u[batch % kPoints] = std::numeric_limits<float>::quiet_NaN();
    du_dx[(batch * 7) % kPoints] = 0.0f, dv_dx[(batch * 7) % kPoints] = 0.0f;
    du_dy[(batch * 7) % kPoints] = 0.0f, dv_dy[(batch * 7) % kPoints] = 0.0f;
    const int n = batch % 3 == 0 ? 1 + batch % kPoints : kPoints;
    const TexturePoints points{n, u, v, du_dx, dv_dx, du_dy, dv_dy};
    glm::vec4 out[kCount * kPoints];
    sample_textures(lookups, kCount, points, out);
    for (int k = 0; k < kCount; ++k)
      for (int i = 0; i < n; ++i) {
        const glm::vec4 expected = sample_texture(*lookups[k].image, *lookups[k].sampler, {u[i], v[i]},
                                                  {du_dx[i], dv_dx[i]}, {du_dy[i], dv_dy[i]});
        CHECK(std::memcmp(&out[k * n + i], &expected, sizeof(glm::vec4)) == 0);
        ++compared;
      }
  }
  CHECK(compared > kCount * 64 * 20);
}

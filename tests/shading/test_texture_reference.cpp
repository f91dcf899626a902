// 8-bit texture lookups against a straightforward reference: every texel
// decoded to double by the formulas (the sRGB curve for an sRGB image's
// colour, code / 255 for every other channel), then the OpenGL 4.6 lookup
// (section 8.14: level of detail, mip selection, wrap, nearest or bilinear
// within a level, linear between levels) evaluated in double. The float
// lookups, one by one and batched, stay within kBound of it: a thirtieth of
// the smallest step between two 8-bit codes' linear values (1 / (255 *
// 12.92), about 3.0e-4, at the dark end of the sRGB curve), so well within
// one code.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "engine/scene/image_mips.h"
#include "engine/shading/texture_sampler.h"

using namespace cr;

namespace {

// Float rounding of the texel coordinates (u * width) dominates: about 3e-6
// on these sizes.
constexpr double kBound = 1e-5;
// Lookups this close (texels, or LOD units) to a point where nearest
// filtering or nearest mip selection jumps are not compared: float and
// double may land on either side.
constexpr double kDecision = 1e-3;

double decode(int code, bool srgb_colour) {
  const double c = code / 255.0;
  if (!srgb_colour) return c;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// The specification's wrap of an integer texel coordinate.
int wrap(long long i, int n, Wrap mode) {
  if (mode == Wrap::ClampToEdge) return int(std::clamp<long long>(i, 0, n - 1));
  if (mode == Wrap::Repeat) return int(((i % n) + n) % n);
  const long long m = ((i % (2 * n)) + 2 * n) % (2 * n);
  return int(m < n ? m : 2 * n - 1 - m);
}

double distance_to_integer(double x) { return std::abs(x - std::round(x)); }

struct Reference {
  const Image& image;
  const Sampler& sampler;
  bool near_decision = false;

  glm::dvec4 texel(int level, int x, int y) const {
    const MipLevel& m = image.mips[size_t(level)];
    const uint8_t* p = &m.rgba[(size_t(y) * size_t(m.width) + size_t(x)) * 4];
    return {decode(p[0], image.srgb), decode(p[1], image.srgb), decode(p[2], image.srgb), decode(p[3], false)};
  }

  glm::dvec4 level_value(int level, double u, double v, Filter filter) {
    const MipLevel& m = image.mips[size_t(level)];
    const double x = u * m.width, y = v * m.height;
    if (filter == Filter::Nearest) {
      near_decision = near_decision || distance_to_integer(x) < kDecision || distance_to_integer(y) < kDecision;
      return texel(level, wrap((long long)std::floor(x), m.width, sampler.wrap_s),
                   wrap((long long)std::floor(y), m.height, sampler.wrap_t));
    }
    const double fx = x - 0.5, fy = y - 0.5;
    const long long x0 = (long long)std::floor(fx), y0 = (long long)std::floor(fy);
    const double ax = fx - double(x0), ay = fy - double(y0);
    const int xa = wrap(x0, m.width, sampler.wrap_s), xb = wrap(x0 + 1, m.width, sampler.wrap_s);
    const int ya = wrap(y0, m.height, sampler.wrap_t), yb = wrap(y0 + 1, m.height, sampler.wrap_t);
    const glm::dvec4 top = texel(level, xa, ya) * (1.0 - ax) + texel(level, xb, ya) * ax;
    const glm::dvec4 bottom = texel(level, xa, yb) * (1.0 - ax) + texel(level, xb, yb) * ax;
    return top * (1.0 - ay) + bottom * ay;
  }

  glm::dvec4 operator()(glm::vec2 uv, glm::vec2 dx, glm::vec2 dy) {
    const double w = image.mips[0].width, h = image.mips[0].height;
    const double rho =
        std::max(std::hypot(double(dx.x) * w, double(dx.y) * h), std::hypot(double(dy.x) * w, double(dy.y) * h));
    const double lambda = rho > 0.0 ? std::log2(rho) : -std::numeric_limits<double>::infinity();
    const double c = sampler.mag == Filter::Linear && sampler.min == Filter::Nearest && sampler.mip ? 0.5 : 0.0;
    if (sampler.mag != sampler.min && std::abs(lambda - c) < kDecision) near_decision = true;
    if (!(lambda > c) || !sampler.mip) return level_value(0, uv.x, uv.y, lambda > c ? sampler.min : sampler.mag);
    const int last = int(image.mips.size()) - 1;
    if (*sampler.mip == Filter::Nearest) {
      if (std::abs(lambda - 0.5) < kDecision || distance_to_integer(lambda + 0.5) < kDecision) near_decision = true;
      const int level = lambda <= 0.5 ? 0 : int(std::min(std::ceil(lambda + 0.5) - 1.0, double(last)));
      return level_value(level, uv.x, uv.y, sampler.min);
    }
    if (lambda >= last) return level_value(last, uv.x, uv.y, sampler.min);
    const int level = int(std::floor(lambda));
    const double t = lambda - level;
    return level_value(level, uv.x, uv.y, sampler.min) * (1.0 - t) +
           level_value(level + 1, uv.x, uv.y, sampler.min) * t;
  }
};

// A w x h chain of random bytes (each level random, not averaged: every
// level's texels differ from its neighbours').
Image random_chain(int w, int h, bool srgb, std::mt19937& rng) {
  Image image;
  image.srgb = srgb;
  MipLevel base{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 4)};
  image.mips.push_back(base);
  generate_mips(image);
  for (MipLevel& m : image.mips)
    for (uint8_t& b : m.rgba) b = uint8_t(rng() & 255u);
  return image;
}

struct Tally {
  double max_error = 0.0;
  int compared = 0, skipped = 0;
  void add(const glm::vec4& value, const glm::dvec4& expected, bool near_decision) {
    if (near_decision) {
      ++skipped;
      return;
    }
    ++compared;
    for (int c = 0; c < 4; ++c) max_error = std::max(max_error, std::abs(double(value[c]) - expected[c]));
  }
};

}  // namespace

TEST_CASE("8-bit lookups match a double-precision decode-then-filter reference: every filter, wrap and LOD") {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f), log_scale(-9.0f, 3.0f), unit(-1.0f, 1.0f);
  const Filter filters[] = {Filter::Nearest, Filter::Linear};
  const Wrap wraps[] = {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat};
  const std::optional<Filter> mips[] = {std::nullopt, Filter::Nearest, Filter::Linear};
  for (glm::ivec2 size : {glm::ivec2(64, 64), glm::ivec2(37, 20), glm::ivec2(1, 9)}) {
    CAPTURE(size.x);
    CAPTURE(size.y);
    // A colour image and a linear one of one size, looked up together: the
    // batch shares their footprint and filters them as a pair.
    const Image images[2] = {random_chain(size.x, size.y, true, rng), random_chain(size.x, size.y, false, rng)};
    Tally single, batched;
    for (Filter mag : filters)
      for (Filter min : filters)
        for (const std::optional<Filter>& mip : mips)
          for (Wrap wrap_s : wraps)
            for (Wrap wrap_t : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
              const Sampler sampler{wrap_s, wrap_t, mag, min, mip};
              constexpr int kPoints = TexturePoints::kCapacity;
              float u[kPoints], v[kPoints], du_dx[kPoints], dv_dx[kPoints], du_dy[kPoints], dv_dy[kPoints];
              for (int i = 0; i < kPoints; ++i) {
                u[i] = coordinate(rng);
                v[i] = coordinate(rng);
                const float s = std::exp2(log_scale(rng));
                du_dx[i] = s * unit(rng);
                dv_dx[i] = s * unit(rng);
                du_dy[i] = s * unit(rng);
                dv_dy[i] = s * unit(rng);
              }
              const TextureLookup lookups[2] = {{&images[0], &sampler}, {&images[1], &sampler}};
              glm::vec4 out[2 * kPoints];
              sample_textures(lookups, 2, TexturePoints{kPoints, u, v, du_dx, dv_dx, du_dy, dv_dy}, out);
              for (int k = 0; k < 2; ++k)
                for (int i = 0; i < kPoints; ++i) {
                  const glm::vec2 uv(u[i], v[i]), dx(du_dx[i], dv_dx[i]), dy(du_dy[i], dv_dy[i]);
                  Reference reference{images[k], sampler};
                  const glm::dvec4 expected = reference(uv, dx, dy);
                  single.add(sample_texture(images[k], sampler, uv, dx, dy), expected, reference.near_decision);
                  batched.add(out[k * kPoints + i], expected, reference.near_decision);
                }
            }
    MESSAGE("max |lookup - reference| ", single.max_error, " (", single.compared, " compared, ", single.skipped,
            " at a nearest-filter or nearest-mip decision)");
    CHECK(single.max_error <= kBound);
    CHECK(batched.max_error <= kBound);
    CHECK(single.compared > 9 * single.skipped);  // decisions are rare
    CHECK(batched.compared == single.compared);
  }
}

#include "engine/shading/texture_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "engine/shading/small_floor.h"
#include "engine/core/srgb.h"

namespace cr {
namespace {

// Value of each 8-bit code of a linear (UNORM) channel, code / 255, so that
// every channel decodes by one lookup like the sRGB ones.
const std::array<float, 256>& unorm_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i) / 255.0f;
    return t;
  }();
  return table;
}

// The decode tables of one image, looked up once per lookup rather than per texel.
struct TexelDecoder {
  const float* rgb;
  const float* alpha;

  explicit TexelDecoder(const Image& image)
      : rgb(image.srgb ? srgb_decode_table().data() : unorm_decode_table().data()),
        alpha(unorm_decode_table().data()) {}

  glm::vec4 operator()(const MipLevel& m, int x, int y) const {
    const uint8_t* p = &m.rgba[(size_t(y) * size_t(m.width) + size_t(x)) * 4];
    return {rgb[p[0]], rgb[p[1]], rgb[p[2]], alpha[p[3]]};
  }
};

// Integer texel index under a wrap mode (OpenGL's formulas for each mode).
// Reduced coordinates (below) put nearly every index inside [0, n) already,
// so that case skips the integer division.
int wrap_index(int i, int n, Wrap wrap) {
  if (unsigned(i) < unsigned(n)) return i;
  switch (wrap) {
    case Wrap::ClampToEdge:
      return std::clamp(i, 0, n - 1);
    case Wrap::MirroredRepeat: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case Wrap::Repeat:
      break;
  }
  int m = i % n;
  return m < 0 ? m + n : m;
}

// Brings a coordinate into a small range with the same wrapped result, so
// that huge or non-finite UVs never overflow the integer texel index.
float reduce_coordinate(float u, Wrap wrap) {
  if (!std::isfinite(u)) return 0.0f;
  // From 2^23 up every float is an integer (u - floor(u) = 0); below, the
  // cheap floor is exact.
  const bool small = std::abs(u) < 8388608.0f;
  switch (wrap) {
    case Wrap::ClampToEdge:
      return std::clamp(u, -1.0f, 2.0f);
    case Wrap::MirroredRepeat:
      return u - 2.0f * (small ? float(floor_to_int(0.5f * u)) : std::floor(0.5f * u));
    case Wrap::Repeat:
      break;
  }
  return small ? u - float(floor_to_int(u)) : 0.0f;
}

// sample_level on coordinates already reduced (they do not depend on the
// level, so trilinear lookups reduce once for both levels).
glm::vec4 sample_reduced(const MipLevel& m, const TexelDecoder& decode, float ru, float rv, Filter filter,
                         Wrap wrap_s, Wrap wrap_t) {
  const float u = ru * float(m.width);
  const float v = rv * float(m.height);
  // Reduced coordinates are small, so floor_to_int applies.
  if (filter == Filter::Nearest) {
    const int x = wrap_index(floor_to_int(u), m.width, wrap_s);
    const int y = wrap_index(floor_to_int(v), m.height, wrap_t);
    return decode(m, x, y);
  }
  // Texel centres sit at integer + 0.5.
  const float fx = u - 0.5f;
  const float fy = v - 0.5f;
  const int xi = floor_to_int(fx);
  const int yi = floor_to_int(fy);
  const float ax = fx - float(xi);
  const float ay = fy - float(yi);
  const int x0 = wrap_index(xi, m.width, wrap_s);
  const int x1 = wrap_index(xi + 1, m.width, wrap_s);
  const int y0 = wrap_index(yi, m.height, wrap_t);
  const int y1 = wrap_index(yi + 1, m.height, wrap_t);
  const glm::vec4 top = glm::mix(decode(m, x0, y0), decode(m, x1, y0), ax);
  const glm::vec4 bottom = glm::mix(decode(m, x0, y1), decode(m, x1, y1), ax);
  return glm::mix(top, bottom, ay);
}

}  // namespace

float texture_lod(const Image& image, glm::vec2 duv_dx, glm::vec2 duv_dy) {
  if (image.mips.empty()) return -std::numeric_limits<float>::infinity();
  const glm::vec2 size(float(image.mips[0].width), float(image.mips[0].height));
  const float rho = std::max(glm::length(duv_dx * size), glm::length(duv_dy * size));
  // NaN derivatives (degenerate triangles) count as no minification.
  if (!(rho > 0.0f)) return -std::numeric_limits<float>::infinity();
  return std::log2(rho);
}

glm::vec4 fetch_texel(const Image& image, int level, int x, int y) {
  return TexelDecoder(image)(image.mips[size_t(level)], x, y);
}

glm::vec4 sample_level(const Image& image, int level, glm::vec2 uv, Filter filter, Wrap wrap_s,
                       Wrap wrap_t) {
  return sample_reduced(image.mips[size_t(level)], TexelDecoder(image), reduce_coordinate(uv.x, wrap_s),
                        reduce_coordinate(uv.y, wrap_t), filter, wrap_s, wrap_t);
}

glm::vec4 sample_texture_at_lod(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda) {
  if (image.mips.empty()) return glm::vec4(1.0f);
  const TexelDecoder decode(image);
  const float ru = reduce_coordinate(uv.x, sampler.wrap_s);
  const float rv = reduce_coordinate(uv.y, sampler.wrap_t);
  auto at_level = [&](int level, Filter filter) {
    return sample_reduced(image.mips[size_t(level)], decode, ru, rv, filter, sampler.wrap_s, sampler.wrap_t);
  };
  // OpenGL's switch-over point: 0.5 when a linear magnification meets a
  // nearest-within-level minification with mipmaps, so the switch is seamless.
  const float c = (sampler.mag == Filter::Linear && sampler.min == Filter::Nearest && sampler.mip) ? 0.5f : 0.0f;
  if (!(lambda > c) || !sampler.mip) return at_level(0, lambda > c ? sampler.min : sampler.mag);
  const int last = int(image.mips.size()) - 1;
  if (*sampler.mip == Filter::Nearest) {
    // OpenGL: d = ceil(lambda + 1/2) - 1 above 1/2, level 0 below.
    const int level = lambda <= 0.5f ? 0 : int(std::min(std::ceil(lambda + 0.5f) - 1.0f, float(last)));
    return at_level(level, sampler.min);
  }
  if (lambda >= float(last)) return at_level(last, sampler.min);
  // Here 0 < lambda < last: small and finite.
  const int level = floor_to_int(lambda);
  const float t = lambda - float(level);
  const glm::vec4 a = at_level(level, sampler.min);
  // mix(a, b, 0) is a exactly (texels are finite): the second level adds nothing.
  if (t == 0.0f) return a;
  return glm::mix(a, at_level(level + 1, sampler.min), t);
}

glm::vec4 sample_texture(const Image& image, const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                         glm::vec2 duv_dy) {
  return sample_texture_at_lod(image, sampler, uv, texture_lod(image, duv_dx, duv_dy));
}

}  // namespace cr

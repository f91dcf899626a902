#include "engine/shading/texture_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/shading/srgb.h"

namespace cr {
namespace {

// Integer texel index under a wrap mode (OpenGL's formulas for each mode).
int wrap_index(int i, int n, Wrap wrap) {
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
  switch (wrap) {
    case Wrap::ClampToEdge:
      return std::clamp(u, -1.0f, 2.0f);
    case Wrap::MirroredRepeat:
      return u - 2.0f * std::floor(0.5f * u);
    case Wrap::Repeat:
      break;
  }
  return u - std::floor(u);
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
  const MipLevel& m = image.mips[size_t(level)];
  const uint8_t* p = &m.rgba[(size_t(y) * size_t(m.width) + size_t(x)) * 4];
  const float alpha = float(p[3]) / 255.0f;
  if (image.srgb) {
    const auto& table = srgb_decode_table();
    return {table[p[0]], table[p[1]], table[p[2]], alpha};
  }
  return {float(p[0]) / 255.0f, float(p[1]) / 255.0f, float(p[2]) / 255.0f, alpha};
}

glm::vec4 sample_level(const Image& image, int level, glm::vec2 uv, Filter filter, Wrap wrap_s,
                       Wrap wrap_t) {
  const MipLevel& m = image.mips[size_t(level)];
  const float u = reduce_coordinate(uv.x, wrap_s) * float(m.width);
  const float v = reduce_coordinate(uv.y, wrap_t) * float(m.height);
  if (filter == Filter::Nearest) {
    const int x = wrap_index(int(std::floor(u)), m.width, wrap_s);
    const int y = wrap_index(int(std::floor(v)), m.height, wrap_t);
    return fetch_texel(image, level, x, y);
  }
  // Texel centres sit at integer + 0.5.
  const float fx = u - 0.5f;
  const float fy = v - 0.5f;
  const float x0f = std::floor(fx);
  const float y0f = std::floor(fy);
  const float ax = fx - x0f;
  const float ay = fy - y0f;
  const int x0 = wrap_index(int(x0f), m.width, wrap_s);
  const int x1 = wrap_index(int(x0f) + 1, m.width, wrap_s);
  const int y0 = wrap_index(int(y0f), m.height, wrap_t);
  const int y1 = wrap_index(int(y0f) + 1, m.height, wrap_t);
  const glm::vec4 top = glm::mix(fetch_texel(image, level, x0, y0), fetch_texel(image, level, x1, y0), ax);
  const glm::vec4 bottom = glm::mix(fetch_texel(image, level, x0, y1), fetch_texel(image, level, x1, y1), ax);
  return glm::mix(top, bottom, ay);
}

glm::vec4 sample_texture(const Image& image, const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                         glm::vec2 duv_dy) {
  if (image.mips.empty()) return glm::vec4(1.0f);
  const float lambda = texture_lod(image, duv_dx, duv_dy);
  // OpenGL's switch-over point: 0.5 when a linear magnification meets a
  // nearest-within-level minification with mipmaps, so the switch is seamless.
  const float c = (sampler.mag == Filter::Linear && sampler.min == Filter::Nearest && sampler.mip) ? 0.5f : 0.0f;
  if (!(lambda > c) || !sampler.mip) {
    const Filter filter = lambda > c ? sampler.min : sampler.mag;
    return sample_level(image, 0, uv, filter, sampler.wrap_s, sampler.wrap_t);
  }
  const int last = int(image.mips.size()) - 1;
  if (*sampler.mip == Filter::Nearest) {
    // OpenGL: d = ceil(lambda + 1/2) - 1 above 1/2, level 0 below.
    const int level = lambda <= 0.5f ? 0 : int(std::min(std::ceil(lambda + 0.5f) - 1.0f, float(last)));
    return sample_level(image, level, uv, sampler.min, sampler.wrap_s, sampler.wrap_t);
  }
  if (lambda >= float(last)) return sample_level(image, last, uv, sampler.min, sampler.wrap_s, sampler.wrap_t);
  const float floor_lambda = std::floor(lambda);
  const int level = int(floor_lambda);
  const float t = lambda - floor_lambda;
  const glm::vec4 a = sample_level(image, level, uv, sampler.min, sampler.wrap_s, sampler.wrap_t);
  const glm::vec4 b = sample_level(image, level + 1, uv, sampler.min, sampler.wrap_s, sampler.wrap_t);
  return glm::mix(a, b, t);
}

}  // namespace cr

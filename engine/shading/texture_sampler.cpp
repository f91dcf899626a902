#include "engine/shading/texture_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>

#include "engine/shading/small_floor.h"
#include "engine/shading/texel_decode.h"
#include "engine/shading/trilinear_footprints.h"

namespace cr {
namespace {

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
inline float reduce_coordinate(float u, Wrap wrap) {
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

// One level's share of a footprint on coordinates already reduced (they do
// not depend on the level, so trilinear lookups reduce once for both levels),
// written in place: returned through the stack, its fields were reloaded in
// pieces that did not match the stores (store-forwarding stalls).
[[gnu::always_inline]] inline void level_footprint(TextureFootprint::Level& f, const MipLevel& m, int index, float ru,
                                                   float rv, Filter filter, Wrap wrap_s, Wrap wrap_t) {
  f.index = index;
  f.ax = f.ay = 0.0f;
  const float u = ru * float(m.width);
  const float v = rv * float(m.height);
  // Reduced coordinates are small, so floor_to_int applies.
  if (filter == Filter::Nearest) {
    const int x = wrap_index(floor_to_int(u), m.width, wrap_s);
    const int y = wrap_index(floor_to_int(v), m.height, wrap_t);
    const uint32_t o = uint32_t(y) * uint32_t(m.width) + uint32_t(x);
    f.texel[0] = f.texel[1] = f.texel[2] = f.texel[3] = o;  // weights 0: the texel itself, exactly
    return;
  }
  // Texel centres sit at integer + 0.5.
  const float fx = u - 0.5f;
  const float fy = v - 0.5f;
  const int xi = floor_to_int(fx);
  const int yi = floor_to_int(fy);
  f.ax = fx - float(xi);
  f.ay = fy - float(yi);
  const uint32_t x0 = uint32_t(wrap_index(xi, m.width, wrap_s));
  const uint32_t x1 = uint32_t(wrap_index(xi + 1, m.width, wrap_s));
  const uint32_t y0 = uint32_t(wrap_index(yi, m.height, wrap_t)) * uint32_t(m.width);
  const uint32_t y1 = uint32_t(wrap_index(yi + 1, m.height, wrap_t)) * uint32_t(m.width);
  f.texel[0] = y0 + x0;
  f.texel[1] = y0 + x1;
  f.texel[2] = y1 + x0;
  f.texel[3] = y1 + x1;
}

// The texels of two images at one index side by side (one AVX register), so
// that the lookups of two images through one footprint blend together.
// Without AVX (x86-64-v2 builds) GCC warns that passing these changes the
// ABI: they never cross a call boundary (internal, inlined), so it does not
// matter. (GCC reports it at the end of the file, so it stays off to there.)
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float TexelPair __attribute__((vector_size(32)));

// The texels of two images at one index side by side: two linear images'
// decoded at once where AVX2 is there (LinearTexels::pair), others one by one.
template <class DecodeA, class DecodeB>
[[gnu::always_inline]] inline TexelPair decode_pair(const DecodeA& decode_a, const DecodeB& decode_b, const uint8_t* a,
                                                    const uint8_t* b) {
#if defined(__AVX2__)
  if constexpr (std::is_same_v<DecodeA, LinearTexels> && std::is_same_v<DecodeB, LinearTexels>)
    return LinearTexels::pair(a, b);
#endif
  return __builtin_shufflevector(decode_a(a), decode_b(b), 0, 1, 2, 3, 4, 5, 6, 7);
}

inline glm::vec4 to_vec4(const Texel& t) {
  glm::vec4 v;
  std::memcpy(&v, &t, sizeof v);
  return v;
}

// glm::mix's arithmetic, lane by lane: x * (1 - t) + y * t.
[[gnu::always_inline]] inline Texel blend(const Texel& x, const Texel& y, float t) { return x * (1.0f - t) + y * t; }
[[gnu::always_inline]] inline TexelPair blend(const TexelPair& x, const TexelPair& y, float t) {
  return x * (1.0f - t) + y * t;
}

// The bilinear blend of the four texels (x0,y0) (x1,y0) (x0,y1) (x1,y1) of
// a level, read by `texel` (index -> linear RGBA, or a pair of them): every
// filtered lookup's.
template <class TexelAt>
[[gnu::always_inline]] inline auto bilinear(const TexelAt& texel, uint32_t t0, uint32_t t1, uint32_t t2, uint32_t t3,
                                            float ax, float ay) {
  const auto top = blend(texel(t0), texel(t1), ax);
  const auto bottom = blend(texel(t2), texel(t3), ax);
  return blend(top, bottom, ay);
}

// body(decode) with the decoder of the image's colour space (texel_decode.h),
// so that the loops inside have no per-texel branch.
template <class Body>
[[gnu::always_inline]] inline auto with_decoder(const Image& image, const Body& body) {
  return image.srgb ? body(SrgbTexels{}) : body(LinearTexels{});
}

// The level's filtered value over its part of a footprint. Always inlined:
// a value returned by value was split across two registers through the stack,
// and the reload stalled on the store.
template <class Decode>
[[gnu::always_inline]] inline Texel sample_level_footprint(const Decode& decode, const Image& image,
                                                           const TextureFootprint::Level& f) {
  const uint8_t* rgba = image.mips[size_t(f.index)].rgba.data();
  return bilinear([&](uint32_t i) { return decode(rgba + size_t(i) * 4); }, f.texel[0], f.texel[1], f.texel[2],
                  f.texel[3], f.ax, f.ay);
}

// texture_footprint written into `f` (which the caller may re-use): a
// footprint returned by value was copied field by field through the stack.
[[gnu::always_inline]] inline void compute_footprint(TextureFootprint& f, const Image& image, const Sampler& sampler,
                                                     glm::vec2 uv, float lambda) {
  f.levels = 0;
  f.t = 0.0f;
  if (image.mips.empty()) return;
  const float ru = reduce_coordinate(uv.x, sampler.wrap_s);
  const float rv = reduce_coordinate(uv.y, sampler.wrap_t);
  auto at_level = [&](int slot, int level, Filter filter) __attribute__((always_inline)) {
    level_footprint(f.level[slot], image.mips[size_t(level)], level, ru, rv, filter, sampler.wrap_s, sampler.wrap_t);
  };
  f.levels = 1;
  // OpenGL's switch-over point: 0.5 when a linear magnification meets a
  // nearest-within-level minification with mipmaps, so the switch is seamless.
  const float c = (sampler.mag == Filter::Linear && sampler.min == Filter::Nearest && sampler.mip) ? 0.5f : 0.0f;
  if (!(lambda > c) || !sampler.mip) {
    at_level(0, 0, lambda > c ? sampler.min : sampler.mag);
    return;
  }
  const int last = int(image.mips.size()) - 1;
  if (*sampler.mip == Filter::Nearest) {
    // OpenGL: d = ceil(lambda + 1/2) - 1 above 1/2, level 0 below.
    const int level = lambda <= 0.5f ? 0 : int(std::min(std::ceil(lambda + 0.5f) - 1.0f, float(last)));
    at_level(0, level, sampler.min);
    return;
  }
  if (lambda >= float(last)) {
    at_level(0, last, sampler.min);
    return;
  }
  // Here 0 < lambda < last: small and finite.
  const int level = floor_to_int(lambda);
  at_level(0, level, sampler.min);
  f.t = lambda - float(level);
  // mix(a, b, 0) is a exactly (texels are finite): the second level adds nothing.
  if (f.t == 0.0f) return;
  at_level(1, level + 1, sampler.min);
  f.levels = 2;
}

// sample_footprint, inlined into the lookups below.
[[gnu::always_inline]] inline glm::vec4 filter_footprint(const Image& image, const TextureFootprint& f) {
  if (f.levels == 0 || image.mips.empty()) return glm::vec4(1.0f);
  return with_decoder(image, [&](const auto& decode) {
    const Texel a = sample_level_footprint(decode, image, f.level[0]);
    if (f.levels == 1) return to_vec4(a);
    return to_vec4(blend(a, sample_level_footprint(decode, image, f.level[1]), f.t));
  });
}

// texture_lod's rho (before the log2) at every point, for a base level of
// size w x h: a vectorised loop (out of line so that the restricts hold).
[[gnu::noinline]] void footprint_scales(int n, float w, float h, const float* __restrict du_dx,
                                        const float* __restrict dv_dx, const float* __restrict du_dy,
                                        const float* __restrict dv_dy, float* __restrict rho) {
  for (int i = 0; i < n; ++i) {
    const float sxx = du_dx[i] * w, sxy = dv_dx[i] * h;
    const float syx = du_dy[i] * w, syy = dv_dy[i] * h;
    const float a = sxx * sxx + sxy * sxy, b = syx * syx + syy * syy;
    rho[i] = std::sqrt(std::max(a, b));
  }
}

// texture_lod at every point for an image with levels: its log2 calls back
// to back, each independent of the last.
void texture_lods(const Image& image, const TexturePoints& p, float* lambda) {
  float rho[TexturePoints::kCapacity];
  footprint_scales(p.count, float(image.mips[0].width), float(image.mips[0].height), p.du_dx, p.dv_dx, p.du_dy,
                   p.dv_dy, rho);
  for (int i = 0; i < p.count; ++i)
    lambda[i] = rho[i] > 0.0f ? std::log2(rho[i]) : -std::numeric_limits<float>::infinity();
}

// filter_footprint at every point of trilinear footprints, texels read by
// `texel(level, index)` and results given to `store(point, value)`: the
// same blends in the same order.
template <class TexelAt, class Store>
[[gnu::always_inline]] inline void filter_trilinear(const TexelAt& texel, const TrilinearFootprints& f, int n,
                                                    const Store& store) {
  for (int i = 0; i < n; ++i) {
    auto level = [&](int s) __attribute__((always_inline)) {
      const int l = f.level[s][i];
      return bilinear([&](uint32_t j) __attribute__((always_inline)) { return texel(l, j); }, f.texel[s][0][i],
                      f.texel[s][1][i], f.texel[s][2][i], f.texel[s][3][i], f.ax[s][i], f.ay[s][i]);
    };
    const auto a = level(0);
    if (f.t[i] == 0.0f) {
      store(i, a);
    } else {
      store(i, blend(a, level(1), f.t[i]));
    }
  }
}

// The RGBA8 texels of every level of an image with a trilinear chain.
struct ChainTexels {
  const uint8_t* level[TrilinearFootprints::kMaxLevels];
  explicit ChainTexels(const Image& image) {
    for (size_t l = 0; l < image.mips.size(); ++l) level[l] = image.mips[l].rgba.data();
  }
  const uint8_t* at(int l, uint32_t i) const { return level[l] + size_t(i) * 4; }
};

// filter_trilinear of one image with levels.
void sample_trilinear(const Image& image, const TrilinearFootprints& f, int n, glm::vec4* out) {
  const ChainTexels texels(image);
  with_decoder(image, [&](const auto& decode) {
    filter_trilinear([&](int l, uint32_t i) { return decode(texels.at(l, i)); }, f, n,
                     [out](int i, const Texel& value) { out[i] = to_vec4(value); });
  });
}

// sample_trilinear of two images of one chain size at once: the footprint is
// read once, and one AVX blend does both.
void sample_trilinear_pair(const Image& a, const Image& b, const TrilinearFootprints& f, int n, glm::vec4* out_a,
                           glm::vec4* out_b) {
  const ChainTexels texels_a(a), texels_b(b);
  with_decoder(a, [&](const auto& decode_a) {
    with_decoder(b, [&](const auto& decode_b) {
      filter_trilinear(
          [&](int l, uint32_t i) __attribute__((always_inline)) {
            return decode_pair(decode_a, decode_b, texels_a.at(l, i), texels_b.at(l, i));
          },
          f, n, [&](int i, const TexelPair& value) __attribute__((always_inline)) {
            std::memcpy(&out_a[i], &value, sizeof(glm::vec4));
            std::memcpy(&out_b[i], reinterpret_cast<const char*>(&value) + sizeof(glm::vec4), sizeof(glm::vec4));
          });
    });
  });
}

}  // namespace

float texture_lod(const Image& image, glm::vec2 duv_dx, glm::vec2 duv_dy) {
  if (image.mips.empty()) return -std::numeric_limits<float>::infinity();
  const glm::vec2 size(float(image.mips[0].width), float(image.mips[0].height));
  const glm::vec2 sx = duv_dx * size, sy = duv_dy * size;
  // max(|sx|, |sy|) with one square root: sqrt is correctly rounded, hence
  // monotonic, so this is the same float (NaN included: std::max keeps its
  // first argument when a comparison fails, before and after the sqrt).
  const float rho = std::sqrt(std::max(glm::dot(sx, sx), glm::dot(sy, sy)));
  // NaN derivatives (degenerate triangles) count as no minification.
  if (!(rho > 0.0f)) return -std::numeric_limits<float>::infinity();
  return std::log2(rho);
}

glm::vec4 fetch_texel(const Image& image, int level, int x, int y) {
  const MipLevel& m = image.mips[size_t(level)];
  const uint8_t* texel = m.rgba.data() + (size_t(y) * size_t(m.width) + size_t(x)) * 4;
  return with_decoder(image, [texel](const auto& decode) { return to_vec4(decode(texel)); });
}

glm::vec4 sample_level(const Image& image, int level, glm::vec2 uv, Filter filter, Wrap wrap_s,
                       Wrap wrap_t) {
  TextureFootprint::Level f;
  level_footprint(f, image.mips[size_t(level)], level, reduce_coordinate(uv.x, wrap_s), reduce_coordinate(uv.y, wrap_t),
                  filter, wrap_s, wrap_t);
  return with_decoder(image, [&](const auto& decode) { return to_vec4(sample_level_footprint(decode, image, f)); });
}

TextureFootprint texture_footprint(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda) {
  TextureFootprint f;
  compute_footprint(f, image, sampler, uv, lambda);
  return f;
}

glm::vec4 sample_footprint(const Image& image, const TextureFootprint& f) { return filter_footprint(image, f); }

glm::vec4 sample_texture_at_lod(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda) {
  return sample_footprint(image, texture_footprint(image, sampler, uv, lambda));
}

glm::vec4 sample_texture(const Image& image, const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                         glm::vec2 duv_dy) {
  return sample_texture_at_lod(image, sampler, uv, texture_lod(image, duv_dx, duv_dy));
}

void sample_textures(const TextureLookup* lookups, int count, glm::vec2 uv, glm::vec2 duv_dx, glm::vec2 duv_dy,
                     glm::vec4* out) {
  // One point of the batch path: out[k * 1 + 0] is lookup k's texel.
  const TexturePoints point{1, &uv.x, &uv.y, &duv_dx.x, &duv_dx.y, &duv_dy.x, &duv_dy.y};
  sample_textures(lookups, count, point, out);
}

void sample_textures(const TextureLookup* lookups, int count, const TexturePoints& points, glm::vec4* out) {
  const int n = points.count;
  int width = -1, height = -1;
  const Sampler* sampler = nullptr;
  bool trilinear = false;
  float lambda[TexturePoints::kCapacity];
  TrilinearFootprints common;
  // Built only for other samplers: zeroing 64 footprints showed in profiles.
  std::optional<std::array<TextureFootprint, TexturePoints::kCapacity>> general;
  for (int k = 0; k < count; ++k) {
    const Image& image = *lookups[k].image;
    glm::vec4* texel = out + size_t(k) * size_t(n);
    if (image.mips.empty()) {  // no levels: opaque white, whatever the footprint
      std::fill(texel, texel + n, glm::vec4(1.0f));
      continue;
    }
    if (image.mips[0].width != width || image.mips[0].height != height) {
      width = image.mips[0].width;
      height = image.mips[0].height;
      sampler = nullptr;
      texture_lods(image, points, lambda);
    }
    if (lookups[k].sampler != sampler) {
      sampler = lookups[k].sampler;
      trilinear = takes_trilinear_footprints(image, *sampler);
      if (trilinear) {
        trilinear_footprints(image, *sampler, points.u, points.v, lambda, n, common);
      } else {
        if (!general) general.emplace();
        for (int i = 0; i < n; ++i)
          compute_footprint((*general)[size_t(i)], image, *sampler, {points.u[i], points.v[i]}, lambda[i]);
      }
    }
    if (trilinear) {
      // The next lookup through the same footprint joins this one (a
      // material's base colour and metallic-roughness, its normal and occlusion).
      const Image* next = k + 1 < count && lookups[k + 1].sampler == sampler ? lookups[k + 1].image : nullptr;
      if (next && next->mips.size() == image.mips.size() && next->mips[0].width == width &&
          next->mips[0].height == height) {
        sample_trilinear_pair(image, *next, common, n, texel, texel + n);
        ++k;
      } else {
        sample_trilinear(image, common, n, texel);
      }
    } else {
      for (int i = 0; i < n; ++i) texel[i] = filter_footprint(image, (*general)[size_t(i)]);
    }
  }
}

}  // namespace cr

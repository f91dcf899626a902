#include "engine/shading/trilinear_footprints.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/shading/small_floor.h"

namespace cr {
namespace {

// reduce_coordinate (texture_sampler.cpp) without branches.
template <Wrap W>
inline float reduced_coordinate(float u) {
  if constexpr (W == Wrap::Repeat) {
    // From 2^23 up, and for inf and NaN, the reduced coordinate is 0, as is
    // that of 0. std::floor rather than floor_to_int: GCC turned the latter's
    // conversion into a branch. Only the sign of a zero result can differ
    // (+0 for -0), which the texel coordinate r * n - 1/2 does not keep.
    const float small = std::abs(u) < 8388608.0f ? u : 0.0f;
    return small - std::floor(small);
  } else {
    static_assert(W == Wrap::ClampToEdge);
    // std::clamp(u, -1, 2) as two selects (nested, they did not vectorise).
    const float above = u < -1.0f ? -1.0f : u;
    const float clamped = 2.0f < above ? 2.0f : above;
    return std::abs(u) <= std::numeric_limits<float>::max() ? clamped : 0.0f;
  }
}

// wrap_index (texture_sampler.cpp) on the indices that reduced coordinates
// give: x = floor(r * n - 1/2) and x + 1 lie in [-1, n] for Repeat (r in
// [0, 1]), where one period up or down wraps them.
template <Wrap W>
inline int32_t wrapped_index(int32_t i, int32_t n) {
  if constexpr (W == Wrap::Repeat) {
    const int32_t up = i + (i < 0 ? n : 0);
    return up - (up >= n ? n : 0);
  }
  return std::min(std::max(i, 0), n - 1);
}

// level_footprint's linear branch for slot `s` of point i. The level's size
// is the base size halved `level` times (a generate_mips chain), computed
// rather than looked up: GCC emulates table gathers with scalar loads.
template <Wrap S, Wrap T>
[[gnu::always_inline]] inline void level_footprint(TrilinearFootprints& f, int s, int i, int32_t level, float ru,
                                                   float rv, int32_t base_width, int32_t base_height) {
  const int32_t w = std::max(base_width >> level, 1), h = std::max(base_height >> level, 1);
  // Texel centres sit at integer + 0.5; reduced coordinates are small, so floor_to_int applies.
  const float fx = ru * float(w) - 0.5f;
  const float fy = rv * float(h) - 0.5f;
  const int32_t xi = floor_to_int(fx), yi = floor_to_int(fy);
  f.level[s][i] = level;
  f.ax[s][i] = fx - float(xi);
  f.ay[s][i] = fy - float(yi);
  const int32_t x0 = wrapped_index<S>(xi, w), x1 = wrapped_index<S>(xi + 1, w);
  const int32_t y0 = wrapped_index<T>(yi, h) * w, y1 = wrapped_index<T>(yi + 1, h) * w;
  f.texel[s][0][i] = uint32_t(y0 + x0);
  f.texel[s][1][i] = uint32_t(y0 + x1);
  f.texel[s][2][i] = uint32_t(y1 + x0);
  f.texel[s][3][i] = uint32_t(y1 + x1);
}

// compute_footprint's linear-mip branch at every point. Out of line so that
// the restricts hold.
template <Wrap S, Wrap T>
[[gnu::noinline]] void footprints(int32_t base_width, int32_t base_height, int32_t last, const float* __restrict u,
                                  const float* __restrict v, const float* __restrict lambda, int count,
                                  TrilinearFootprints& __restrict f) {
  const float last_level = float(last);
  for (int i = 0; i < count; ++i) {
    const float ru = reduced_coordinate<S>(u[i]), rv = reduced_coordinate<T>(v[i]);
    // Level 0 alone at or below lambda 0 (NaN included), the last level
    // alone at or past it; in between floor(lambda) blends with the next.
    const float positive = lambda[i] > 0.0f ? lambda[i] : 0.0f;
    const float clamped = positive < last_level ? positive : last_level;
    const int32_t level = int32_t(clamped);  // clamped >= 0: truncation is floor
    f.t[i] = clamped - float(level);
    level_footprint<S, T>(f, 0, i, level, ru, rv, base_width, base_height);
    level_footprint<S, T>(f, 1, i, level < last ? level + 1 : last, ru, rv, base_width, base_height);
  }
}

}  // namespace

bool takes_trilinear_footprints(const Image& image, const Sampler& sampler) {
  auto simple = [](Wrap w) { return w == Wrap::Repeat || w == Wrap::ClampToEdge; };
  if (sampler.mag != Filter::Linear || sampler.min != Filter::Linear || sampler.mip != Filter::Linear ||
      !simple(sampler.wrap_s) || !simple(sampler.wrap_t) || image.mips.empty())
    return false;
  for (size_t l = 1; l < image.mips.size(); ++l)
    if (image.mips[l].width != std::max(1, image.mips[l - 1].width / 2) ||
        image.mips[l].height != std::max(1, image.mips[l - 1].height / 2))
      return false;
  return true;
}

void trilinear_footprints(const Image& image, const Sampler& sampler, const float* u, const float* v,
                          const float* lambda, int count, TrilinearFootprints& out) {
  const bool repeat_s = sampler.wrap_s == Wrap::Repeat, repeat_t = sampler.wrap_t == Wrap::Repeat;
  auto run = repeat_s ? (repeat_t ? footprints<Wrap::Repeat, Wrap::Repeat> : footprints<Wrap::Repeat, Wrap::ClampToEdge>)
                      : (repeat_t ? footprints<Wrap::ClampToEdge, Wrap::Repeat>
                                  : footprints<Wrap::ClampToEdge, Wrap::ClampToEdge>);
  run(image.mips[0].width, image.mips[0].height, int32_t(image.mips.size()) - 1, u, v, lambda, count, out);
}

}  // namespace cr

#include "fog/volume_shadow.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <immintrin.h>

namespace cr {

namespace {

// The per-ray constants of the eight-lane lookup.
struct LaneConstants {
  __m256 ox, oy, oz, sx, sy, sz;  // the ray in texel space
  __m256 size, minus_one, one, zero, last_origin, bias, top;
  __m256i size_i;
};

// 1 where the occluder is not nearer than the receiver, else 0.
__attribute__((target("avx2"))) inline __m256 lit_tap(__m256 occluder, __m256 receiver, __m256 one) {
  return _mm256_and_ps(_mm256_cmp_ps(occluder, receiver, _CMP_LE_OQ), one);
}

// Taps (x0, x0 + 1) of one row of the footprints at texels origin[i] + row:
// points (0,1,4,5) fill `even`, (2,3,6,7) `odd`, so one in-lane shuffle puts
// each tap in point order.
__attribute__((target("avx2"))) inline void row_taps(const float* depth, const uint32_t* origin, size_t row,
                                                     __m256& even, __m256& odd) {
  auto pair = [&](int i, int j) {
    const __m128 first = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(depth + origin[i] + row)));
    return _mm_loadh_pi(first, reinterpret_cast<const __m64*>(depth + origin[j] + row));
  };
  even = _mm256_insertf128_ps(_mm256_castps128_ps256(pair(0, 1)), pair(4, 5), 1);
  odd = _mm256_insertf128_ps(_mm256_castps128_ps256(pair(2, 3)), pair(6, 7), 1);
}

// visibility at the eight points t8 into out8; lanes from `valid` on are
// padding (no edge lookup). See visibility_avx2.
__attribute__((target("avx2"), always_inline)) inline void lookup8(const VolumeShadow& shadow, const VolumeShadow::Ray& r,
                                                    const float* depth, int size, const LaneConstants& c,
                                                    const float* t8, int valid, float* out8) {
  const __m256 t = _mm256_loadu_ps(t8);
  const __m256 tx = _mm256_add_ps(c.ox, _mm256_mul_ps(t, c.sx));
  const __m256 ty = _mm256_add_ps(c.oy, _mm256_mul_ps(t, c.sy));
  const __m256 rc = _mm256_add_ps(c.oz, _mm256_mul_ps(t, c.sz));
  __m256 inside = _mm256_and_ps(_mm256_cmp_ps(tx, c.minus_one, _CMP_GE_OQ), _mm256_cmp_ps(ty, c.minus_one, _CMP_GE_OQ));
  inside = _mm256_and_ps(inside, _mm256_and_ps(_mm256_cmp_ps(tx, c.size, _CMP_LE_OQ), _mm256_cmp_ps(ty, c.size, _CMP_LE_OQ)));
  inside = _mm256_and_ps(inside, _mm256_and_ps(_mm256_cmp_ps(rc, c.bias, _CMP_GE_OQ), _mm256_cmp_ps(rc, c.top, _CMP_LE_OQ)));
  const __m256 fx = _mm256_floor_ps(tx), fy = _mm256_floor_ps(ty);
  const __m256 ax = _mm256_sub_ps(tx, fx), ay = _mm256_sub_ps(ty, fy);
  // All four taps on the map: the footprint's origin in [0, size - 2]^2.
  __m256 on_map = _mm256_and_ps(_mm256_cmp_ps(fx, c.zero, _CMP_GE_OQ), _mm256_cmp_ps(fx, c.last_origin, _CMP_LE_OQ));
  on_map = _mm256_and_ps(on_map, _mm256_and_ps(_mm256_cmp_ps(fy, c.zero, _CMP_GE_OQ), _mm256_cmp_ps(fy, c.last_origin, _CMP_LE_OQ)));
  on_map = _mm256_and_ps(on_map, inside);
  const __m256 on_edge = _mm256_andnot_ps(on_map, inside);
  // Other points read texel 0 (in range; their result is replaced).
  const __m256i texel = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(fy), c.size_i), _mm256_cvttps_epi32(fx));
  alignas(32) uint32_t origin[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(origin), _mm256_and_si256(_mm256_castps_si256(on_map), texel));
  __m256 even0, odd0, even1, odd1;
  row_taps(depth, origin, 0, even0, odd0);
  row_taps(depth, origin, size_t(size), even1, odd1);
  const __m256 l00 = lit_tap(_mm256_shuffle_ps(even0, odd0, _MM_SHUFFLE(2, 0, 2, 0)), rc, c.one);
  const __m256 l10 = lit_tap(_mm256_shuffle_ps(even0, odd0, _MM_SHUFFLE(3, 1, 3, 1)), rc, c.one);
  const __m256 l01 = lit_tap(_mm256_shuffle_ps(even1, odd1, _MM_SHUFFLE(2, 0, 2, 0)), rc, c.one);
  const __m256 l11 = lit_tap(_mm256_shuffle_ps(even1, odd1, _MM_SHUFFLE(3, 1, 3, 1)), rc, c.one);
  const __m256 top = _mm256_add_ps(l00, _mm256_mul_ps(_mm256_sub_ps(l10, l00), ax));
  const __m256 bottom = _mm256_add_ps(l01, _mm256_mul_ps(_mm256_sub_ps(l11, l01), ax));
  const __m256 v = _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ay));
  _mm256_storeu_ps(out8, _mm256_blendv_ps(c.one, v, inside));
  for (int edge = _mm256_movemask_ps(on_edge) & ((1 << valid) - 1); edge != 0; edge &= edge - 1) {
    const int j = __builtin_ctz(unsigned(edge));
    out8[j] = shadow.visibility(r, t8[j]);
  }
}

// visibility(r, t[k]) for k < n, eight points at a time. The tap positions,
// bilinear weights and range tests run in AVX2 lanes; each point's four taps
// are two 8-byte loads (its rows y0 and y0 + 1, two taps each) packed two
// points to a 128-bit half and put in point order by in-lane shuffles (AVX2
// gathers, 4 per 8 points, measured ~2x slower on Zen4). Points whose 2x2
// footprint crosses the map's edge (a tap off the map, which counts as lit)
// take the one-point lookup. The lane arithmetic is
// VolumeShadow::visibility's sequence of float operations, so both paths
// give the same bits.
__attribute__((target("avx2"))) void visibility_avx2(const VolumeShadow& shadow, const float* depth, int size,
                                                     float bias, const VolumeShadow::Ray& r, const float* t_in,
                                                     int n, float* visibility) {
  LaneConstants c;
  c.ox = _mm256_set1_ps(r.origin.x), c.oy = _mm256_set1_ps(r.origin.y), c.oz = _mm256_set1_ps(r.origin.z);
  c.sx = _mm256_set1_ps(r.step.x), c.sy = _mm256_set1_ps(r.step.y), c.sz = _mm256_set1_ps(r.step.z);
  c.size = _mm256_set1_ps(float(size)), c.minus_one = _mm256_set1_ps(-1.0f), c.one = _mm256_set1_ps(1.0f);
  c.zero = _mm256_setzero_ps(), c.last_origin = _mm256_set1_ps(float(size - 2));
  c.bias = _mm256_set1_ps(bias), c.top = _mm256_set1_ps(1.0f + bias);
  c.size_i = _mm256_set1_epi32(size);
  int k = 0;
  for (; k + 8 <= n; k += 8) lookup8(shadow, r, depth, size, c, t_in + k, 8, visibility + k);
  if (k == n) return;
  // The last 1-7 points as one block padded with copies of the last point
  // (a column's slice count is rarely a multiple of 8).
  alignas(32) float t_tail[8], tail[8];
  for (int j = 0; j < 8; ++j) t_tail[j] = t_in[std::min(k + j, n - 1)];
  lookup8(shadow, r, depth, size, c, t_tail, n - k, tail);
  for (int j = 0; k + j < n; ++j) visibility[k + j] = tail[j];
}

}  // namespace

VolumeShadow::VolumeShadow(const ShadowMap& map, const glm::dvec3& camera_position) {
  if (map.size <= 0 || map.depth.size() < size_t(map.size) * size_t(map.size)) return;
  size_ = map.size;
  depth_ = map.depth.data();
  // clip = M (rel + camera - origin). Texel coordinates (centres at +0.5,
  // minus 0.5 for the bilinear footprint): x = (clip.x + 1)/2 size - 0.5,
  // y = (1 - clip.y)/2 size - 0.5. Depth gets ShadowMap's constant bias.
  const glm::vec3 offset(camera_position - map.origin);
  const float s = float(size_);
  const float bias = 0.5f * map.texel_world_size / map.depth_range + 1.0f / float(1 << 20);
  glm::mat4 texel(1.0f);
  texel[0][0] = 0.5f * s;
  texel[1][1] = -0.5f * s;
  texel[3][0] = 0.5f * s - 0.5f;
  texel[3][1] = 0.5f * s - 0.5f;
  texel[3][2] = bias;
  bias_ = bias;
  glm::mat4 translate(1.0f);
  translate[3] = glm::vec4(offset, 1.0f);
  to_texel_ = texel * map.light_view_proj * translate;
}

VolumeShadow::Ray VolumeShadow::ray(const glm::vec3& origin_rel, const glm::vec3& direction) const {
  Ray r;
  r.origin = glm::vec3(to_texel_ * glm::vec4(origin_rel, 1.0f));
  r.step = glm::vec3(to_texel_ * glm::vec4(direction, 0.0f));
  return r;
}

void VolumeShadow::visibility(const Ray& r, const float* t, int n, float* out) const {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (size_ >= 2 && avx2) {
    visibility_avx2(*this, depth_, size_, bias_, r, t, n, out);
    return;
  }
  for (int k = 0; k < n; ++k) out[k] = visibility(r, t[k]);
}

}  // namespace cr

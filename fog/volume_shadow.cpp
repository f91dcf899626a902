#include "fog/volume_shadow.h"

#include <cmath>

#include <immintrin.h>

namespace cr {

namespace {

// Lanes of v outside [0, last]: taps off the map.
__attribute__((target("avx2"))) inline __m256i outside_map(__m256i v, __m256i last) {
  return _mm256_or_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), v), _mm256_cmpgt_epi32(v, last));
}
__attribute__((target("avx2"))) inline __m256i clamp_to_map(__m256i v, __m256i last) {
  return _mm256_min_epi32(_mm256_max_epi32(v, _mm256_setzero_si256()), last);
}
// 1 where the tap is lit (off the map, or the occluder is not nearer), else 0.
__attribute__((target("avx2"))) inline __m256 lit_tap(const float* depth, __m256 receiver, __m256i row, __m256i col,
                                                      __m256i off_map) {
  const __m256 d = _mm256_i32gather_ps(depth, _mm256_add_epi32(row, col), 4);
  const __m256 lit = _mm256_or_ps(_mm256_cmp_ps(d, receiver, _CMP_LE_OQ), _mm256_castsi256_ps(off_map));
  return _mm256_and_ps(lit, _mm256_set1_ps(1.0f));
}

// visibility(r, t[k]) for k < n, eight points at a time with AVX2 gathers
// (clamped tap indices, off-map taps lit). The lane arithmetic is
// VolumeShadow::visibility's sequence of float operations, so both paths give
// the same bits.
__attribute__((target("avx2"))) void visibility_avx2(const VolumeShadow& shadow, const float* depth, int size,
                                                     float bias, const VolumeShadow::Ray& r, const float* t_in,
                                                     int n, float* visibility) {
  const glm::vec3 o = r.origin, st = r.step;
  const __m256 ox = _mm256_set1_ps(o.x), oy = _mm256_set1_ps(o.y), oz = _mm256_set1_ps(o.z);
  const __m256 sx = _mm256_set1_ps(st.x), sy = _mm256_set1_ps(st.y), sz = _mm256_set1_ps(st.z);
  const __m256 s = _mm256_set1_ps(float(size)), minus_one = _mm256_set1_ps(-1.0f), one = _mm256_set1_ps(1.0f);
  const __m256 lo = _mm256_set1_ps(bias), hi = _mm256_set1_ps(1.0f + bias);
  const __m256i last = _mm256_set1_epi32(size - 1), one_i = _mm256_set1_epi32(1);
  const __m256i size_i = _mm256_set1_epi32(size);
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256 t = _mm256_loadu_ps(t_in + k);
    const __m256 tx = _mm256_add_ps(ox, _mm256_mul_ps(t, sx));
    const __m256 ty = _mm256_add_ps(oy, _mm256_mul_ps(t, sy));
    const __m256 rc = _mm256_add_ps(oz, _mm256_mul_ps(t, sz));
    __m256 inside = _mm256_and_ps(_mm256_cmp_ps(tx, minus_one, _CMP_GE_OQ), _mm256_cmp_ps(ty, minus_one, _CMP_GE_OQ));
    inside = _mm256_and_ps(inside, _mm256_and_ps(_mm256_cmp_ps(tx, s, _CMP_LE_OQ), _mm256_cmp_ps(ty, s, _CMP_LE_OQ)));
    inside = _mm256_and_ps(inside, _mm256_and_ps(_mm256_cmp_ps(rc, lo, _CMP_GE_OQ), _mm256_cmp_ps(rc, hi, _CMP_LE_OQ)));
    // Clamp before flooring so lanes outside stay in integer range.
    const __m256 fx = _mm256_floor_ps(_mm256_min_ps(_mm256_max_ps(tx, minus_one), s));
    const __m256 fy = _mm256_floor_ps(_mm256_min_ps(_mm256_max_ps(ty, minus_one), s));
    const __m256 ax = _mm256_sub_ps(tx, fx), ay = _mm256_sub_ps(ty, fy);
    const __m256i x0 = _mm256_cvttps_epi32(fx), y0 = _mm256_cvttps_epi32(fy);
    const __m256i x1 = _mm256_add_epi32(x0, one_i), y1 = _mm256_add_epi32(y0, one_i);
    const __m256i ox0 = outside_map(x0, last), ox1 = outside_map(x1, last);
    const __m256i oy0 = outside_map(y0, last), oy1 = outside_map(y1, last);
    const __m256i cx0 = clamp_to_map(x0, last), cx1 = clamp_to_map(x1, last);
    const __m256i cy0 = _mm256_mullo_epi32(clamp_to_map(y0, last), size_i);
    const __m256i cy1 = _mm256_mullo_epi32(clamp_to_map(y1, last), size_i);
    const __m256 l00 = lit_tap(depth, rc, cy0, cx0, _mm256_or_si256(oy0, ox0));
    const __m256 l10 = lit_tap(depth, rc, cy0, cx1, _mm256_or_si256(oy0, ox1));
    const __m256 l01 = lit_tap(depth, rc, cy1, cx0, _mm256_or_si256(oy1, ox0));
    const __m256 l11 = lit_tap(depth, rc, cy1, cx1, _mm256_or_si256(oy1, ox1));
    const __m256 top = _mm256_add_ps(l00, _mm256_mul_ps(_mm256_sub_ps(l10, l00), ax));
    const __m256 bottom = _mm256_add_ps(l01, _mm256_mul_ps(_mm256_sub_ps(l11, l01), ax));
    const __m256 v = _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ay));
    _mm256_storeu_ps(visibility + k, _mm256_blendv_ps(one, v, inside));
  }
  for (; k < n; ++k) visibility[k] = shadow.visibility(r, t_in[k]);
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
  if (size_ > 0 && avx2) {
    visibility_avx2(*this, depth_, size_, bias_, r, t, n, out);
    return;
  }
  for (int k = 0; k < n; ++k) out[k] = visibility(r, t[k]);
}

}  // namespace cr

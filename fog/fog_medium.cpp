#include "fog/fog_medium.h"

#include <algorithm>
#include <cmath>

#include <immintrin.h>

#include "engine/core/fast_math.h"
#include "fog/value_noise.h"

namespace cr {

FogMedium::FogMedium(const FogSceneSettings& settings) : settings_(settings) {
  // HDRP: the density falls to 0.001 of the base at max_height:
  // exp(-d / H) = 0.001 gives H = d / ln(1000) = 0.144765 d.
  const float layer = std::max(0.01f, settings.max_height - settings.base_height);
  inv_scale_height_ = 1.0f / (layer * 0.144765f);
  cutoff_above_ = 2.0f * layer;  // exp(-2 ln 1000) = 1e-6
}

void FogMedium::set_camera(const glm::dvec3& camera_position) {
  base_rel_ = float(double(settings_.base_height) - camera_position.y);
  placed_.clear();
  for (size_t i = 0; i < settings_.volumes.size(); ++i) {
    const FogVolume& v = settings_.volumes[i];
    if (!(v.half_size.x > 0.0f && v.half_size.y > 0.0f && v.half_size.z > 0.0f)) continue;
    PlacedFogVolume p;
    p.center = glm::vec3(v.center - camera_position);
    for (int a = 0; a < 3; ++a) p.axes[a] = v.axes[a];
    p.half_size = v.half_size;
    p.fade = v.fade;
    p.density.extinction = v.extinction;
    p.density.scattering = v.albedo * v.extinction;
    p.blend = v.blend;
    p.noise = v.noise;
    p.source_index = int(i);
    placed_.push_back(p);
  }
}

FogDensity FogMedium::height_fog(const glm::vec3& rel) const {
  FogDensity d;
  if (!settings_.height_fog) return d;
  const float above = std::max(rel.y - base_rel_, 0.0f);
  const float m = above > cutoff_above_ ? 0.0f : fast_exp(-above * inv_scale_height_);
  d.extinction = settings_.extinction * m;
  d.scattering = settings_.albedo * d.extinction;
  return d;
}

namespace {

// records[j] = (albedo e[j], e[j]) for the j < m in whole groups of eight
// (returns how many): the three products in lanes, then a 4x8 transpose into
// four 2-record stores (written field by field the compiler scatters each
// lane into 4 scalar stores).
__attribute__((target("avx2"))) int store_records_avx2(const float* e, int m, const glm::vec3& albedo,
                                                       float* records) {
  const __m256 ax = _mm256_set1_ps(albedo.x), ay = _mm256_set1_ps(albedo.y), az = _mm256_set1_ps(albedo.z);
  int j = 0;
  for (; j + 8 <= m; j += 8) {
    const __m256 ext = _mm256_loadu_ps(e + j);
    const __m256 r = _mm256_mul_ps(ax, ext), g = _mm256_mul_ps(ay, ext), b = _mm256_mul_ps(az, ext);
    const __m256 rg_lo = _mm256_unpacklo_ps(r, g), rg_hi = _mm256_unpackhi_ps(r, g);  // r0 g0 r1 g1 | r4 g4 r5 g5
    const __m256 be_lo = _mm256_unpacklo_ps(b, ext), be_hi = _mm256_unpackhi_ps(b, ext);
    const __m256 rec04 = _mm256_shuffle_ps(rg_lo, be_lo, _MM_SHUFFLE(1, 0, 1, 0));  // record 0 | record 4
    const __m256 rec15 = _mm256_shuffle_ps(rg_lo, be_lo, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 rec26 = _mm256_shuffle_ps(rg_hi, be_hi, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 rec37 = _mm256_shuffle_ps(rg_hi, be_hi, _MM_SHUFFLE(3, 2, 3, 2));
    float* out = records + 4 * size_t(j);
    _mm256_storeu_ps(out, _mm256_permute2f128_ps(rec04, rec15, 0x20));
    _mm256_storeu_ps(out + 8, _mm256_permute2f128_ps(rec26, rec37, 0x20));
    _mm256_storeu_ps(out + 16, _mm256_permute2f128_ps(rec04, rec15, 0x31));
    _mm256_storeu_ps(out + 24, _mm256_permute2f128_ps(rec26, rec37, 0x31));
  }
  return j;
}

}  // namespace

// The extinction loop is branch-free over a flat float array (vectorised);
// the records are then filled eight at a time where the CPU has AVX2. Per
// lane the same float operations as height_fog (no contraction).
void FogMedium::height_fog_column(const glm::vec3& dir, const float* t, int n, FogDensity* out) const {
  if (!settings_.height_fog) {
    for (int k = 0; k < n; ++k) out[k] = FogDensity{};
    return;
  }
  static_assert(sizeof(FogDensity) == 4 * sizeof(float));
  const glm::vec3 albedo = settings_.albedo;
  const float extinction = settings_.extinction;
  float* records = reinterpret_cast<float*>(out);
  static const bool avx2 = __builtin_cpu_supports("avx2");
  constexpr int kBlock = 64;
  float e[kBlock];
  for (int k0 = 0; k0 < n; k0 += kBlock) {
    const int m = std::min(kBlock, n - k0);
    for (int j = 0; j < m; ++j) {
      const float above = std::max(dir.y * t[k0 + j] - base_rel_, 0.0f);
      const float falloff = fast_exp(-above * inv_scale_height_);  // unconditional: the select is a blend
      e[j] = extinction * (above > cutoff_above_ ? 0.0f : falloff);
    }
    int j = avx2 ? store_records_avx2(e, m, albedo, records + 4 * size_t(k0)) : 0;
    for (; j < m; ++j) {
      out[k0 + j].extinction = e[j];
      out[k0 + j].scattering = albedo * e[j];
    }
  }
}

bool FogMedium::apply_volume(const PlacedFogVolume& v, const glm::vec3& rel, FogDensity& dst) const {
  const glm::vec3 o = rel - v.center;
  const glm::vec3 local(glm::dot(o, v.axes[0]), glm::dot(o, v.axes[1]), glm::dot(o, v.axes[2]));
  const glm::vec3 inside = v.half_size - glm::abs(local);  // distance to each face pair
  const float nearest_face = std::min(inside.x, std::min(inside.y, inside.z));
  if (!(nearest_face >= 0.0f)) return false;
  float fade = 1.0f;
  if (v.fade > 0.0f) fade = std::min(nearest_face / v.fade, 1.0f);
  FogDensity src = v.density;
  if (v.noise.enabled) {
    const float n = fractal_noise(local / v.noise.scale, v.noise.octaves);
    const float m = 1.0f + (n - 1.0f) * v.noise.strength;
    src.extinction *= m;
    src.scattering *= m;
  }
  // Every mode is "lerp(dst, op(dst, src), fade)": the fade blends the
  // operation in, so no mode opens a gap at the volume's edge.
  FogDensity op;
  switch (v.blend) {
    case FogBlend::Overwrite: op = src; break;
    case FogBlend::Additive:
      op.scattering = dst.scattering + src.scattering;
      op.extinction = dst.extinction + src.extinction;
      break;
    case FogBlend::Multiply:  // the volume's values act as factors
      op.scattering = dst.scattering * src.scattering;
      op.extinction = dst.extinction * src.extinction;
      break;
    case FogBlend::Min:
      op.scattering = glm::min(dst.scattering, src.scattering);
      op.extinction = std::min(dst.extinction, src.extinction);
      break;
    case FogBlend::Max:
      op.scattering = glm::max(dst.scattering, src.scattering);
      op.extinction = std::max(dst.extinction, src.extinction);
      break;
  }
  dst.scattering += (op.scattering - dst.scattering) * fade;
  dst.extinction += (op.extinction - dst.extinction) * fade;
  return true;
}

FogDensity FogMedium::sample(const glm::vec3& rel) const {
  FogDensity d = height_fog(rel);
  for (const PlacedFogVolume& v : placed_) apply_volume(v, rel, d);
  return d;
}

}  // namespace cr

#include "engine/shading/environment_brdf.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/brdf.h"
#include "engine/shading/ggx_sampling.h"

namespace cr {

EnvironmentBrdf integrate_environment_brdf(float roughness, float n_dot_v, int samples) {
  const float r = clamp_nan_safe(roughness, kMinRoughness, 1.0f);
  const float alpha = r * r;
  const float nv = clamp_nan_safe(n_dot_v, 1e-3f, 1.0f);
  const glm::vec3 v(std::sqrt(1.0f - nv * nv), 0.0f, nv);
  double a = 0.0, b = 0.0;
  for (int i = 0; i < samples; ++i) {
    const glm::vec3 h = ggx_half_vector(hammersley(uint32_t(i), uint32_t(samples)), alpha);
    const float vh = glm::dot(v, h);
    const float nl = 2.0f * vh * h.z - nv;  // (reflect(-v, h)).z
    if (nl <= 0.0f || vh <= 0.0f) continue;
    // f nl / pdf with pdf(l) = D (n.h) / (4 v.h): D cancels.
    const float weight = smith_visibility(nl, nv, alpha) * 4.0f * nl * vh / h.z;
    const float fc = fresnel_weight(vh);
    a += double((1.0f - fc) * weight);
    b += double(fc * weight);
  }
  return {float(a / samples), float(b / samples)};
}

DfgTable::DfgTable() {
  for (int j = 0; j < kSize; ++j)
    for (int i = 0; i < kSize; ++i) {
      const EnvironmentBrdf e =
          integrate_environment_brdf(float(j) / float(kSize - 1), float(i) / float(kSize - 1), kSamples);
      // Node i is cell i's left half and cell i - 1's right half.
      if (i < kSize - 1) {
        cells_[size_t(j * kRow + i * 4)] = e.a;
        cells_[size_t(j * kRow + i * 4 + 1)] = e.b;
      }
      if (i > 0) {
        cells_[size_t(j * kRow + i * 4 - 2)] = e.a;
        cells_[size_t(j * kRow + i * 4 - 1)] = e.b;
      }
    }
}

namespace {

typedef float Float4 __attribute__((vector_size(16)));

inline Float4 load4(const float* p) {
  Float4 t;
  __builtin_memcpy(&t, p, sizeof(t));
  return t;
}

}  // namespace

void DfgTable::lookup_batch(size_t n, const float* __restrict roughness, const float* __restrict n_dot_v,
                            float* __restrict a, float* __restrict b) const {
  constexpr size_t kChunk = 64;
  int first[kChunk];
  float wx[kChunk], wy[kChunk];
  for (size_t start = 0; start < n; start += kChunk) {
    const size_t m = n - start < kChunk ? n - start : kChunk;
    for (size_t i = 0; i < m; ++i) {
      const Cell c = cell(roughness[start + i], n_dot_v[start + i]);
      first[i] = c.first;
      wx[i] = c.wx;
      wy[i] = c.wy;
    }
    for (size_t i = 0; i < m; ++i) {
      // lookup()'s operations, lane for lane: {A, B} of both rows, left and right.
      const float* r0 = &cells_[size_t(first[i])];
      const Float4 row0 = load4(r0), row1 = load4(r0 + kRow);
      const Float4 left = __builtin_shufflevector(row0, row1, 0, 1, 4, 5);
      const Float4 right = __builtin_shufflevector(row0, row1, 2, 3, 6, 7);
      const Float4 x = left + (right - left) * wx[i];  // {a0, b0, a1, b1}
      const Float4 lo = __builtin_shufflevector(x, x, 0, 1, 0, 1), hi = __builtin_shufflevector(x, x, 2, 3, 2, 3);
      const Float4 y = lo + (hi - lo) * wy[i];
      a[start + i] = y[0];
      b[start + i] = y[1];
    }
  }
}

const DfgTable& DfgTable::get() {
  static const DfgTable table;
  return table;
}

}  // namespace cr

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
      a_[size_t(j * kSize + i)] = e.a;
      b_[size_t(j * kSize + i)] = e.b;
    }
}

void DfgTable::lookup_batch(size_t n, const float* __restrict roughness, const float* __restrict n_dot_v,
                            float* __restrict a, float* __restrict b) const {
  for (size_t i = 0; i < n; ++i) {
    const EnvironmentBrdf e = lookup(roughness[i], n_dot_v[i]);
    a[i] = e.a;
    b[i] = e.b;
  }
}

const DfgTable& DfgTable::get() {
  static const DfgTable table;
  return table;
}

}  // namespace cr

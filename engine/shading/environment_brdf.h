#pragma once
// Directional albedo of the specular lobe under uniform lighting, split as
// f0 * A + B (the "split sum" environment BRDF, Karis 2013): a table over
// (n.v, perceptual roughness) of the glTF BRDF's specular lobe (GGX,
// height-correlated Smith, Schlick), integrated once by importance sampling.
// Used for the ambient specular term and to take the specularly reflected
// share away from the ambient diffuse term.
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

namespace cr {

struct EnvironmentBrdf {
  float a = 1.0f;  // scale of f0
  float b = 0.0f;  // bias
  glm::vec3 albedo(const glm::vec3& f0) const { return f0 * a + b; }
};

// A and B at one (roughness, n.v) by importance sampling the GGX half vector
// with `samples` Hammersley points: the table's integrand, for building and testing it.
// roughness is floored at kMinRoughness and n_dot_v at 1e-3 (what shading sees).
EnvironmentBrdf integrate_environment_brdf(float roughness, float n_dot_v, int samples);

// The table: kSize x kSize nodes at n.v = i/(kSize-1), roughness = j/(kSize-1)
// (kSamples points each, ~15 ms once), read bilinearly. Inline lookup, no
// branches: batched shading loops vectorise over it.
class DfgTable {
 public:
  static constexpr int kSize = 32;
  static constexpr int kSamples = 1024;
  // Built on first use (thread-safe), then shared.
  static const DfgTable& get();

  EnvironmentBrdf lookup(float roughness, float n_dot_v) const {
    const float fx = clamp01(n_dot_v) * float(kSize - 1);
    const float fy = clamp01(roughness) * float(kSize - 1);
    const int x0 = int(fx) < kSize - 2 ? int(fx) : kSize - 2;
    const int y0 = int(fy) < kSize - 2 ? int(fy) : kSize - 2;
    const float wx = fx - float(x0), wy = fy - float(y0);
    const int i = y0 * kSize + x0;
    const float a0 = a_[i] + (a_[i + 1] - a_[i]) * wx;
    const float a1 = a_[i + kSize] + (a_[i + kSize + 1] - a_[i + kSize]) * wx;
    const float b0 = b_[i] + (b_[i + 1] - b_[i]) * wx;
    const float b1 = b_[i + kSize] + (b_[i + kSize + 1] - b_[i + kSize]) * wx;
    return {a0 + (a1 - a0) * wy, b0 + (b1 - b0) * wy};
  }
  // lookup() of n points into a[i], b[i], bit for bit, in a loop that
  // vectorises (gathers; inlined into a larger loop, the table's loads
  // would keep that loop scalar).
  void lookup_batch(size_t n, const float* roughness, const float* n_dot_v, float* a, float* b) const;
  // Node values (for tests).
  EnvironmentBrdf node(int n_dot_v_index, int roughness_index) const {
    const int i = roughness_index * kSize + n_dot_v_index;
    return {a_[i], b_[i]};
  }

 private:
  DfgTable();
  static float clamp01(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }  // NaN -> 0
  std::array<float, kSize * kSize> a_{};
  std::array<float, kSize * kSize> b_{};
};

// roughness: perceptual, in [0, 1]; n_dot_v: cosine of the view angle.
inline EnvironmentBrdf environment_brdf(float roughness, float n_dot_v) {
  return DfgTable::get().lookup(roughness, n_dot_v);
}

}  // namespace cr

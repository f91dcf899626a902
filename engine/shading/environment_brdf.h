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
// (kSamples points each, ~15 ms once), read bilinearly. Stored by cell: each
// node with its n.v neighbour, {A, B, A right, B right}, so that a lookup is
// two 16-byte rows.
class DfgTable {
 public:
  static constexpr int kSize = 32;
  static constexpr int kSamples = 1024;
  // Built on first use (thread-safe), then shared.
  static const DfgTable& get();

  EnvironmentBrdf lookup(float roughness, float n_dot_v) const {
    const Cell c = cell(roughness, n_dot_v);
    const float* r0 = &cells_[size_t(c.first)];
    const float* r1 = r0 + kRow;
    const float a0 = r0[0] + (r0[2] - r0[0]) * c.wx, b0 = r0[1] + (r0[3] - r0[1]) * c.wx;
    const float a1 = r1[0] + (r1[2] - r1[0]) * c.wx, b1 = r1[1] + (r1[3] - r1[1]) * c.wx;
    return {a0 + (a1 - a0) * c.wy, b0 + (b1 - b0) * c.wy};
  }
  // lookup() of n points into a[i], b[i], bit for bit: the cells and weights
  // in a loop that vectorises, then two 16-byte loads per point (faster than
  // the 8 gathers of one vectorised loop).
  void lookup_batch(size_t n, const float* roughness, const float* n_dot_v, float* a, float* b) const;
  // Node values (for tests).
  EnvironmentBrdf node(int n_dot_v_index, int roughness_index) const {
    const int i = n_dot_v_index < kSize - 1 ? n_dot_v_index : kSize - 2;
    const float* c = &cells_[size_t(roughness_index * kRow + i * 4)];
    return n_dot_v_index < kSize - 1 ? EnvironmentBrdf{c[0], c[1]} : EnvironmentBrdf{c[2], c[3]};
  }

 private:
  DfgTable();
  static constexpr int kRow = (kSize - 1) * 4;  // floats per roughness row of cells
  struct Cell {
    int first;  // the lower row's first float
    float wx, wy;
  };
  static float clamp01(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }  // NaN -> 0
  static Cell cell(float roughness, float n_dot_v) {
    const float fx = clamp01(n_dot_v) * float(kSize - 1);
    const float fy = clamp01(roughness) * float(kSize - 1);
    const int x0 = int(fx) < kSize - 2 ? int(fx) : kSize - 2;
    const int y0 = int(fy) < kSize - 2 ? int(fy) : kSize - 2;
    return {y0 * kRow + x0 * 4, fx - float(x0), fy - float(y0)};
  }
  std::array<float, kSize * kRow> cells_{};
};

// roughness: perceptual, in [0, 1]; n_dot_v: cosine of the view angle.
inline EnvironmentBrdf environment_brdf(float roughness, float n_dot_v) {
  return DfgTable::get().lookup(roughness, n_dot_v);
}

}  // namespace cr

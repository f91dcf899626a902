#pragma once
// Directional albedo of the glTF BRDF by deterministic quadrature, shared by
// the BRDF and split-sum tests (an integration independent of the DFG
// table's importance sampling).
#include <algorithm>
#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/shading/brdf.h"

namespace cr::test {

// Directional albedo E(v) = integral of f(l, v) (n.l) over the hemisphere,
// n = +Z, by deterministic quadrature: a stratified grid of cosine-weighted
// directions and one of GGX-distributed half vectors, combined with the
// balance heuristic so both the diffuse part and narrow highlights converge.
inline float directional_albedo(const BrdfParams& p, float n_dot_v, const glm::vec3& channel_weights = glm::vec3(1, 0, 0)) {
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  const glm::vec3 v(std::sqrt(1.0f - n_dot_v * n_dot_v), 0.0f, n_dot_v);
  const float roughness = std::clamp(p.roughness, kMinRoughness, 1.0f);
  const float alpha = roughness * roughness;
  constexpr int kGrid = 160;
  auto pdf_cosine = [](const glm::vec3& l) { return std::max(l.z, 0.0f) / kPi; };
  auto pdf_ggx = [&](const glm::vec3& l) {
    const glm::vec3 h = glm::normalize(l + v);
    const float v_dot_h = glm::dot(v, h);
    return v_dot_h > 0.0f ? ggx_distribution(h.z, alpha) * h.z / (4.0f * v_dot_h) : 0.0f;
  };
  double sum = 0.0;
  auto add = [&](const glm::vec3& l) {
    if (l.z <= 0.0f) return;
    const float pdf = pdf_cosine(l) + pdf_ggx(l);
    if (!(pdf > 0.0f)) return;
    sum += double(glm::dot(evaluate_brdf(p, n, v, l), channel_weights)) * l.z / pdf;
  };
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const float u1 = (float(i) + 0.5f) / kGrid;
      const float u2 = (float(j) + 0.5f) / kGrid;
      const float phi = 2.0f * kPi * u2;
      const float r = std::sqrt(u1);
      add({r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0f - u1)});
      const float cos_h = std::sqrt((1.0f - u1) / (1.0f + (alpha * alpha - 1.0f) * u1));
      const float sin_h = std::sqrt(std::max(0.0f, 1.0f - cos_h * cos_h));
      const glm::vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
      add(2.0f * glm::dot(v, h) * h - v);
    }
  }
  return float(sum / (double(kGrid) * kGrid));
}

}  // namespace cr::test

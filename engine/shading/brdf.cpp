#include "engine/shading/brdf.h"

#include <algorithm>
#include <cmath>

namespace cr {
namespace {

constexpr float kPi = 3.14159265358979f;

float fresnel_weight(float v_dot_h) {
  const float w = 1.0f - std::min(std::abs(v_dot_h), 1.0f);
  const float w2 = w * w;
  return w2 * w2 * w;
}

// Clamp that maps NaN to the lower bound (std::clamp passes NaN through).
float clamp_nan_safe(float x, float lo, float hi) { return x > lo ? (x < hi ? x : hi) : lo; }

}  // namespace

float ggx_distribution(float n_dot_h, float alpha) {
  if (!(n_dot_h > 0.0f)) return 0.0f;
  const float a2 = alpha * alpha;
  const float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float smith_visibility(float n_dot_l, float n_dot_v, float alpha) {
  const float a2 = alpha * alpha;
  const float nl = std::abs(n_dot_l);
  const float nv = std::abs(n_dot_v);
  const float denom = nv * std::sqrt(a2 + (1.0f - a2) * nl * nl) + nl * std::sqrt(a2 + (1.0f - a2) * nv * nv);
  return denom > 0.0f ? 0.5f / denom : 0.0f;
}

glm::vec3 schlick_fresnel(const glm::vec3& f0, float v_dot_h) {
  return f0 + (glm::vec3(1.0f) - f0) * fresnel_weight(v_dot_h);
}

glm::vec3 specular_f0(const BrdfParams& p) {
  return glm::mix(glm::vec3(kDielectricF0), p.base_color, clamp_nan_safe(p.metallic, 0.0f, 1.0f));
}

glm::vec3 evaluate_brdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& v, const glm::vec3& l) {
  const float n_dot_l = glm::dot(n, l);
  const float n_dot_v = glm::dot(n, v);
  if (!(n_dot_l > 0.0f) || !(n_dot_v > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 sum = l + v;
  const float sum_len = glm::length(sum);
  // l == -v cannot happen with both above the surface, except by rounding.
  if (!(sum_len > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 h = sum / sum_len;
  const float v_dot_h = glm::dot(v, h);
  const float n_dot_h = glm::dot(n, h);

  const float metallic = clamp_nan_safe(p.metallic, 0.0f, 1.0f);
  const float roughness = clamp_nan_safe(p.roughness, kMinRoughness, 1.0f);
  const float alpha = roughness * roughness;
  const float w = fresnel_weight(v_dot_h);
  // Heaviside terms chi+(H.L) chi+(H.V): H.L == H.V for the half vector.
  const float specular = v_dot_h > 0.0f ? ggx_distribution(n_dot_h, alpha) * smith_visibility(n_dot_l, n_dot_v, alpha) : 0.0f;
  const glm::vec3 f0 = specular_f0(p);
  const glm::vec3 f = f0 + (glm::vec3(1.0f) - f0) * w;
  const float dielectric_fresnel = kDielectricF0 + (1.0f - kDielectricF0) * w;
  const glm::vec3 diffuse = ((1.0f - metallic) * (1.0f - dielectric_fresnel) / kPi) * p.base_color;
  return diffuse + f * specular;
}

}  // namespace cr

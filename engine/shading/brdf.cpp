#include "engine/shading/brdf.h"

namespace cr {

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
  const BrdfTerms t = brdf_terms(n_dot_l, n_dot_v, glm::dot(n, h), glm::dot(v, h), p.metallic, p.roughness);
  const glm::vec3 f0 = specular_f0(p);
  return t.diffuse * p.base_color + (f0 + (glm::vec3(1.0f) - f0) * t.fresnel_w) * t.specular;
}

}  // namespace cr

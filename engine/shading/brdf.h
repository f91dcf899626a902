#pragma once
// The glTF 2.0 metallic-roughness BRDF, as written in the specification's
// Appendix B ("Full code"):
//   alpha = roughness^2, D = Trowbridge-Reitz/GGX, Vis = height-correlated Smith,
//   fresnel_w = (1 - |V.H|)^5
//   dielectric = mix(baseColor/pi, D*Vis, 0.04 + 0.96 fresnel_w)          (fresnel_mix)
//   metal      = D*Vis * (baseColor + (1 - baseColor) fresnel_w)          (conductor_fresnel)
//   f          = mix(dielectric, metal, metallic)
// The specular parts combine into Schlick's F with f0 = mix(0.04, baseColor,
// metallic); the diffuse part is (1 - metallic) (1 - F_dielectric) baseColor/pi,
// which equals the often-quoted (1 - F) mix(baseColor, 0, metallic)/pi at
// metallic 0 and 1 and follows the specification in between.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "engine/core/math_constants.h"

namespace cr {

// Least perceptual roughness shaded. The sun is a delta light here; with
// roughness 0.045 (alpha^2 = 4.1e-6) a highlight's peak radiance D*Vis*E is
// about E/(4 pi alpha^2) ~ E / 5e-5 sr, the sun's own radiance (its disc spans
// 6.8e-5 sr): smoother surfaces would reflect a sun brighter than the sun, and
// D's 1/alpha^2 would head for overflow. Filament uses the same bound.
inline constexpr float kMinRoughness = 0.045f;
inline constexpr float kDielectricF0 = 0.04f;  // ior 1.5

struct BrdfParams {
  glm::vec3 base_color{1.0f};  // linear
  float metallic = 0.0f;
  float roughness = 1.0f;      // perceptual; clamped to [kMinRoughness, 1]
};

// Clamp that maps NaN to the lower bound (std::clamp passes NaN through).
inline float clamp_nan_safe(float x, float lo, float hi) { return x > lo ? (x < hi ? x : hi) : lo; }

// The functions below are inline and free of branches the compiler cannot
// turn into selects, so batched shading loops over them vectorise.

// Trowbridge-Reitz/GGX normal distribution (alpha = roughness^2).
inline float ggx_distribution(float n_dot_h, float alpha) {
  const float a2 = alpha * alpha;
  const float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  const float value = a2 / (kPi * d * d);
  return n_dot_h > 0.0f ? value : 0.0f;
}

// Height-correlated Smith visibility Vis = G / (4 |N.L| |N.V|).
inline float smith_visibility(float n_dot_l, float n_dot_v, float alpha) {
  const float a2 = alpha * alpha;
  const float nl = std::abs(n_dot_l);
  const float nv = std::abs(n_dot_v);
  const float denom = nv * std::sqrt(a2 + (1.0f - a2) * nl * nl) + nl * std::sqrt(a2 + (1.0f - a2) * nv * nv);
  return denom > 0.0f ? 0.5f / denom : 0.0f;
}

// Schlick's weight (1 - |V.H|)^5.
inline float fresnel_weight(float v_dot_h) {
  const float w = 1.0f - std::min(std::abs(v_dot_h), 1.0f);
  const float w2 = w * w;
  return w2 * w2 * w;
}

// The scalar parts of the BRDF for one light; per channel
// f = diffuse * baseColor + (f0 + (1 - f0) * fresnel_w) * specular.
// All zero when l or v lies below the surface. Inputs: cosines of unit
// vectors, metallic and perceptual roughness as in BrdfParams.
struct BrdfTerms {
  float diffuse = 0.0f;
  float specular = 0.0f;
  float fresnel_w = 0.0f;
};
inline BrdfTerms brdf_terms(float n_dot_l, float n_dot_v, float n_dot_h, float v_dot_h, float metallic,
                            float roughness) {
  const bool above = n_dot_l > 0.0f && n_dot_v > 0.0f;
  const float m = clamp_nan_safe(metallic, 0.0f, 1.0f);
  const float r = clamp_nan_safe(roughness, kMinRoughness, 1.0f);
  const float alpha = r * r;
  const float w = fresnel_weight(v_dot_h);
  // Heaviside terms chi+(H.L) chi+(H.V): H.L == H.V for the half vector.
  const float specular = ggx_distribution(n_dot_h, alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
  const float dielectric_fresnel = kDielectricF0 + (1.0f - kDielectricF0) * w;
  BrdfTerms t;
  t.diffuse = above ? (1.0f - m) * (1.0f - dielectric_fresnel) / kPi : 0.0f;
  t.specular = above && v_dot_h > 0.0f ? specular : 0.0f;
  t.fresnel_w = w;
  return t;
}

// f0 of one colour channel: mix(0.04, base, metallic), metallic in [0, 1].
inline float channel_f0(float base, float metallic) { return kDielectricF0 + (base - kDielectricF0) * metallic; }

// One delta light at a shading point: brdf_terms over the half vector of
// unit l and v (n_dot_l = n.l, n_dot_v = n.v for unit n), and the cosine n.l
// where light and viewer are above the surface, else 0. Batched lighting
// loops (the sun, point and spot lights) share it.
struct LightReflection {
  BrdfTerms terms;
  float cosine = 0.0f;
};
inline LightReflection light_reflection(float nx, float ny, float nz, float vx, float vy, float vz, float lx,
                                        float ly, float lz, float n_dot_l, float n_dot_v, float metallic,
                                        float roughness) {
  const float hx = lx + vx, hy = ly + vy, hz = lz + vz;
  const float hlen = std::sqrt(hx * hx + hy * hy + hz * hz);
  const bool lit = n_dot_l > 0.0f && n_dot_v > 0.0f && hlen > 0.0f;
  const float inv_h = hlen > 0.0f ? 1.0f / hlen : 0.0f;
  const float n_dot_h = (nx * hx + ny * hy + nz * hz) * inv_h;
  const float v_dot_h = (vx * hx + vy * hy + vz * hz) * inv_h;
  return {brdf_terms(n_dot_l, n_dot_v, n_dot_h, v_dot_h, metallic, roughness), lit ? n_dot_l : 0.0f};
}
// f(l, v) * n.l of one colour channel (base colour `base`, f0 `f0`): times the
// light's illuminance, the radiance it reflects.
inline float reflected(const LightReflection& r, float base, float f0) {
  return (r.terms.diffuse * base + (f0 + (1.0f - f0) * r.terms.fresnel_w) * r.terms.specular) * r.cosine;
}

// Schlick's Fresnel with f90 = 1.
glm::vec3 schlick_fresnel(const glm::vec3& f0, float v_dot_h);
// f0 = mix(0.04, baseColor, metallic).
glm::vec3 specular_f0(const BrdfParams& p);

// The BRDF f(l, v) for unit normal n, view v and light l (without the cosine
// factor). Zero when l or v lies below the surface. Finite for all unit inputs.
glm::vec3 evaluate_brdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& v, const glm::vec3& l);

}  // namespace cr

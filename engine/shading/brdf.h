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
#include <glm/glm.hpp>

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

// Trowbridge-Reitz/GGX normal distribution (alpha = roughness^2).
float ggx_distribution(float n_dot_h, float alpha);
// Height-correlated Smith visibility Vis = G / (4 |N.L| |N.V|).
float smith_visibility(float n_dot_l, float n_dot_v, float alpha);
// Schlick's Fresnel with f90 = 1.
glm::vec3 schlick_fresnel(const glm::vec3& f0, float v_dot_h);
// f0 = mix(0.04, baseColor, metallic).
glm::vec3 specular_f0(const BrdfParams& p);

// The BRDF f(l, v) for unit normal n, view v and light l (without the cosine
// factor). Zero when l or v lies below the surface. Finite for all unit inputs.
glm::vec3 evaluate_brdf(const BrdfParams& p, const glm::vec3& n, const glm::vec3& v, const glm::vec3& l);

}  // namespace cr

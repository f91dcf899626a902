#include "engine/shading/shade_surface.h"

#include <cmath>

#include "engine/shading/brdf.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/safe_normalize.h"
#include "engine/shading/sh_lighting.h"

namespace cr {
namespace {

constexpr float kPi = 3.14159265358979f;
// Least n.v shaded: normal maps and interpolated normals can face away from
// the viewer, where the BRDF is undefined; such normals are bent back just
// far enough to be seen (a cheap form of the usual "visible normal" fix).
constexpr float kMinNdotV = 1e-3f;

glm::vec3 finite_or_zero(const glm::vec3& c) {
  return {std::isfinite(c.x) ? c.x : 0.0f, std::isfinite(c.y) ? c.y : 0.0f, std::isfinite(c.z) ? c.z : 0.0f};
}

}  // namespace

SurfaceShader::SurfaceShader(const ShadingInputs& in)
    : scene_(in.scene),
      light_(in.light),
      shadow_(in.shadow && in.shadow->size > 0 ? in.shadow : nullptr),
      camera_position_(in.camera_position),
      sun_direction_(normalize_or(in.light->sun_direction, glm::vec3(0.0f, 1.0f, 0.0f))),
      ambient_(in.light->ambient_sh) {}

glm::vec4 SurfaceShader::shade(const Material& material, const SurfaceSample& surface) const {
  const MaterialSample m = evaluate_material(*scene_, material, surface);
  const glm::vec3 interpolated_normal = normalize_or(surface.normal, glm::vec3(0.0f, 1.0f, 0.0f));
  const glm::vec3 v = normalize_or(glm::vec3(camera_position_ - glm::dvec3(surface.position)), interpolated_normal);
  glm::vec3 n = m.normal;
  const float n_dot_v_raw = glm::dot(n, v);
  if (!(n_dot_v_raw >= kMinNdotV)) n = normalize_or(n + v * (kMinNdotV - n_dot_v_raw), v);
  const float n_dot_v = std::max(glm::dot(n, v), kMinNdotV);

  const BrdfParams brdf{m.base_color, m.metallic, m.roughness};
  const LightEnvironment& light = *light_;
  glm::vec3 radiance = m.emissive;

  const glm::vec3& l = sun_direction_;
  const float n_dot_l = glm::dot(n, l);
  if (n_dot_l > 0.0f) {
    const glm::vec3 sun = sun_illuminance_at(light, surface.position);
    if (sun != glm::vec3(0.0f)) {
      // The shadow lookup uses the interpolated normal: its bias models the
      // geometry in the depth map, which the normal map does not change.
      const float visibility = shadow_ ? shadow_->visibility(surface.position, interpolated_normal) : 1.0f;
      if (visibility > 0.0f) radiance += evaluate_brdf(brdf, n, v, l) * (n_dot_l * visibility) * sun;
    }
  }

  const EnvironmentBrdf env = environment_brdf(std::max(m.roughness, kMinRoughness), n_dot_v);
  const glm::vec3 irradiance = glm::max(ambient_.irradiance(n), glm::vec3(0.0f));
  const glm::vec3 reflected = glm::max(ambient_.radiance(glm::reflect(-v, n)), glm::vec3(0.0f));
  const glm::vec3 diffuse =
      irradiance * ((1.0f - m.metallic) * (1.0f - env.albedo(glm::vec3(kDielectricF0)).x) / kPi) * m.base_color;
  const glm::vec3 specular = reflected * env.albedo(specular_f0(brdf));
  radiance += (diffuse + specular) * m.occlusion;

  const float alpha = material.alpha_mode == AlphaMode::Blend ? m.alpha : 1.0f;
  return {finite_or_zero(radiance), alpha};
}

glm::vec4 shade_surface(const ShadingInputs& in, const Material& material, const SurfaceSample& surface) {
  return SurfaceShader(in).shade(material, surface);
}

}  // namespace cr

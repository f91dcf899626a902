#pragma once
// Lighting of one surface point: the sun (with its shadow) and the scene's
// point and spot lights through the glTF BRDF, ambient sky light (diffuse
// from SH, specular from a prefiltered environment or SH), emission. Returns linear radiance (cd/m^2) towards the camera and the
// opacity used for blending.
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/punctual_lights.h"
#include "engine/shading/sh_lighting.h"
#include "engine/shading/shading_batch.h"
#include "engine/shading/shadow_map.h"
#include "engine/shading/surface.h"

namespace cr {

struct ShadingInputs {
  const Scene* scene = nullptr;
  const LightEnvironment* light = nullptr;
  const ShadowMap* shadow = nullptr;  // null or size 0: unshadowed
  glm::dvec3 camera_position{0.0};
  // cd/m^2 of glTF emissive 1.0 and of unlit base colour 1.0 (material_eval.h);
  // the renderer passes emissive_luminance(scene description).
  float emissive_luminance = 1.0f;
};

// rgb: radiance leaving the surface towards the camera, not premultiplied.
// a: 1 for OPAQUE and MASK (fragments below the cutoff never get here),
// material_alpha for BLEND. Every component is finite for any input.
//
// sun      = BRDF(n, v, l) * max(n.l, 0) * E_sun * shadow visibility, E_sun =
//            light->sun_at(position) when set, else light->sun_illuminance;
// lights   = sum over scene->lights of BRDF(n, v, l) * max(n.l, 0) * E, E as
//            punctual_lights.h says (no shadows);
// ambient  = ao * E_sh(n) * (1 - metallic) baseColor/pi * (1 - albedo_spec(0.04))
//            + so * L_spec * albedo_spec(f0),
//            ao = the occlusion map, so = specular_occlusion(n.v, ao, alpha)
//            (specular_occlusion.h), albedo_spec = f0 A + B from the split-sum
//            DFG table (environment_brdf.h) at (roughness, n.v);
//            L_spec = light->specular->sample(d, roughness) when an environment
//            is set, d = mix(R, n, alpha) (R = reflect(-v, n), bent towards n
//            for rough lobes), else L_sh(R) (the fallback: the SH ambient lights
//            both lobes); E_sh / L_sh = SH irradiance / radiance, clamped at 0;
//            roughness perceptual in [kMinRoughness, 1], alpha = roughness^2,
//            n.v floored at 1e-3;
// emission = emissive factor * strength * texture * in.emissive_luminance.
// Unlit materials: baseColor * in.emissive_luminance alone.
glm::vec4 shade_surface(const ShadingInputs& in, const Material& material, const SurfaceSample& surface);

// shade_surface for many points of one frame, with what does not depend on
// the point (sun direction, SH band factors, shadow map presence) prepared
// once, and points lit in batches (vectorised loops, one sun_at call per
// batch; the point and spot lights' loop skipped when the scene has none).
// Same results as shade_surface for every point of a batch. Holds pointers
// into `in`'s scene, light and shadow map, which must outlive it and not
// change meanwhile (the scene's lights are read at construction).
class SurfaceShader {
 public:
  explicit SurfaceShader(const ShadingInputs& in);
  glm::vec4 shade(const Material& material, const SurfaceSample& surface) const;
  // Evaluates the material at the surface point and appends it to the batch
  // (which must not be full).
  void add(ShadingBatch& batch, const Material& material, const SurfaceSample& surface) const;
  // Lights every point of the batch: radiance in out_r/g/b, opacity in alpha.
  void shade_batch(ShadingBatch& batch) const;

 private:
  const Scene* scene_;
  const LightEnvironment* light_;
  const ShadowMap* shadow_;  // null when unshadowed
  glm::dvec3 camera_position_;
  float emissive_luminance_;
  glm::vec3 sun_direction_;  // unit
  ShLighting ambient_;
  const SpecularEnvironment* specular_;  // null: SH specular (light_'s, shared)
  const DfgTable* dfg_;
  std::vector<PunctualLightTerms> lights_;
};

}  // namespace cr

#pragma once
// A glTF metallic-roughness material evaluated at one surface point: factors
// times textures times vertex colour, the normal map applied.
#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/shading/surface.h"
#include "engine/shading/texture_sampler.h"

namespace cr {

// Luminance (cd/m^2) of emissive colour 1.0. glTF leaves emissive unitless;
// 1000 cd/m^2 is a bright display or lit sign: it reads as glowing at night
// and indoor exposures (EV100 5-10, where white is 38-1200 cd/m^2) and, as
// real signs do, fades next to sunlit surfaces (EV100 ~15, white ~39000 cd/m^2).
inline constexpr float kEmissiveNits = 1000.0f;

struct MaterialSample {
  glm::vec3 base_color{1.0f};  // linear: factor * texture * vertex colour
  float alpha = 1.0f;          // factor * texture alpha * vertex colour alpha
  float metallic = 1.0f;
  float roughness = 1.0f;      // perceptual, before the BRDF's minimum
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  // unit, world space, normal map applied
  float occlusion = 1.0f;      // ambient occlusion after strength
  glm::vec3 emissive{0.0f};    // cd/m^2
};

// The default sampler of glTF ("repeat wrapping and auto filtering"): trilinear.
const Sampler& default_sampler();

// Linear RGBA of a material texture at the surface (its LOD from the surface's
// UV derivatives); opaque white when the reference holds no image.
glm::vec4 sample_material_texture(const Scene& scene, const TextureRef& ref, const SurfaceSample& surface);

// Base colour alpha: factor * texture alpha * vertex colour alpha, in [0, 1].
// Coverage for MASK (compared with alpha_cutoff) and opacity for BLEND.
float material_alpha(const Scene& scene, const Material& material, const SurfaceSample& surface);

// Whether shading the material reads SurfaceSample::tangent (its normal map
// does): interpolate_surface can skip the tangent frame otherwise.
inline bool needs_tangent(const Material& material) { return material.normal.valid(); }

MaterialSample evaluate_material(const Scene& scene, const Material& material, const SurfaceSample& surface);

// A material's textures as sample_textures reads them together (they share
// footprints): set up once for the many points shaded with the material.
struct MaterialTextures {
  enum Slot { kBaseColor, kMetallicRoughness, kNormal, kOcclusion, kEmissive, kSlots };
  TextureLookup lookups[kSlots];
  int lookup_of[kSlots]{};  // slot -> lookup; -1: no texture, reads as opaque white (the neutral factor)
  int count = 0;

  MaterialTextures() = default;
  MaterialTextures(const Scene& scene, const Material& material);
};

// evaluate_material up to the normal map, from the texels of the material's
// lookups (sample_textures of `textures`: lookup k's at texels[k * stride])
// and the vertex colour: every field of `m` but the normal. With a normal
// map, `tangent_normal` gets its tangent-space normal (XY scaled), which
// evaluate_material turns into world space point by point and
// evaluate_materials (material_batch.h) batch-wide.
void evaluate_material_factors(const Material& material, const MaterialTextures& textures, const glm::vec4* texels,
                               int stride, const glm::vec4& color, MaterialSample& m, glm::vec3& tangent_normal);

}  // namespace cr

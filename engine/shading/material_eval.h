#pragma once
// A glTF metallic-roughness material evaluated at one surface point: factors
// times textures times vertex colour, the normal map applied. Textures read
// their own UV set (TEXCOORD_0 or _1) through their own KHR_texture_transform.
//
// Emission: glTF leaves emissive colour unitless; the renderer maps emissive
// 1.0 (emissiveFactor * texture * KHR_materials_emissive_strength) to the
// scene's emissive luminance (emissive_luminance of scene_description.h: the
// exposure's white unless the scene file says otherwise), so that emissive
// 1.0 shows as white, as glTF viewers show it. Unlit materials
// (KHR_materials_unlit) leave base colour * that luminance, unlit.
#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/shading/surface.h"
#include "engine/shading/texture_sampler.h"
#include "engine/shading/uv_transform.h"

namespace cr {

struct MaterialSample {
  glm::vec3 base_color{1.0f};  // linear: factor * texture * vertex colour
  float alpha = 1.0f;          // factor * texture alpha * vertex colour alpha
  float metallic = 1.0f;
  float roughness = 1.0f;      // perceptual, before the BRDF's minimum
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  // unit, world space, normal map applied
  float occlusion = 1.0f;      // ambient occlusion after strength
  glm::vec3 emissive{0.0f};    // cd/m^2; for an unlit material its whole radiance
  bool unlit = false;          // KHR_materials_unlit: emissive is the radiance, no light is added
};

// The default sampler of glTF ("repeat wrapping and auto filtering"): trilinear.
const Sampler& default_sampler();

// Linear RGBA of a material texture at the surface, at the reference's UV set
// and transform (its LOD from the transformed UV derivatives); opaque white
// when the reference holds no image.
glm::vec4 sample_material_texture(const Scene& scene, const TextureRef& ref, const SurfaceSample& surface);

// Base colour alpha: factor * texture alpha * vertex colour alpha, in [0, 1].
// Coverage for MASK (compared with alpha_cutoff) and opacity for BLEND.
float material_alpha(const Scene& scene, const Material& material, const SurfaceSample& surface);

// Whether shading the material reads SurfaceSample::tangent (its normal map
// does; unlit materials ignore it): interpolate_surface can skip the tangent
// frame otherwise.
inline bool needs_tangent(const Material& material) { return material.normal.valid() && !material.unlit; }

// Whether shading the material reads TEXCOORD_1 (SurfaceSample::uv1): a
// texture of it uses set 1. Surfaces interpolate the set only then.
inline bool needs_uv1(const Material& m) {
  auto reads_uv1 = [](const TextureRef& t) { return t.valid() && t.texcoord == 1; };
  if (m.unlit) return reads_uv1(m.base_color);
  return reads_uv1(m.base_color) || reads_uv1(m.metallic_roughness) || reads_uv1(m.normal) ||
         reads_uv1(m.occlusion) || reads_uv1(m.emissive);
}

// Whether the material emits: emissive factor and strength not zero.
inline bool emits(const Material& material) {
  return material.emissive_factor != glm::vec3(0.0f) && material.emissive_strength != 0.0f;
}

// Radiance (cd/m^2) per unit of emissive texture: emissiveFactor *
// emissive_strength * the luminance of emissive 1.0.
inline glm::vec3 emissive_scale(const Material& material, float emissive_luminance) {
  return material.emissive_factor * (material.emissive_strength * emissive_luminance);
}

// `emissive_luminance`: cd/m^2 of emissive 1.0 (the header's convention).
MaterialSample evaluate_material(const Scene& scene, const Material& material, const SurfaceSample& surface,
                                 float emissive_luminance);

// A material's textures as sample_material_textures reads them together:
// set up once for the many points shaded with the material. Lookups that
// read the same coordinates (UV set and transform) are adjacent, one channel,
// so that sample_textures shares their footprints; slots differing in either
// are separate channels.
struct MaterialTextures {
  enum Slot { kBaseColor, kMetallicRoughness, kNormal, kOcclusion, kEmissive, kSlots };
  // Trivial (set up per run of points): only the first channel_count are set.
  struct UvChannel {
    int texcoord;        // 0: TEXCOORD_0, 1: TEXCOORD_1
    bool transformed;    // KHR_texture_transform other than the identity
    UvAffine transform;  // when transformed
    int first, count;    // its lookups
  };
  TextureLookup lookups[kSlots];
  int lookup_of[kSlots]{};  // slot -> lookup; -1: no texture, reads as opaque white (the neutral factor)
  int count = 0;
  UvChannel channels[kSlots];
  int channel_count = 0;
  // Tangent-space XY of the normal map into the surface's frame when the
  // map's UVs are transformed (normal_map_turn; set only then).
  bool normal_turned = false;
  NormalMapTurn normal_turn;

  MaterialTextures() = default;
  MaterialTextures(const Scene& scene, const Material& material);
};

// Every lookup of `textures` at the points, each through its channel's UV
// set and transform: lookup k's texel of point i at out[k * n + i], n =
// uv[0].count. uv[s] holds the points' TEXCOORD_s (uv[1] is read only when a
// channel uses set 1; both of n points). Inline: it runs once per run of
// points sharing a material.
inline void sample_material_textures(const MaterialTextures& textures, const TexturePoints* uv, glm::vec4* out) {
  const size_t n = size_t(uv[0].count);
  TransformedUvs transformed;
  for (int c = 0; c < textures.channel_count; ++c) {
    const MaterialTextures::UvChannel& channel = textures.channels[c];
    const TexturePoints& points = uv[channel.texcoord];
    sample_textures(textures.lookups + channel.first, channel.count,
                    channel.transformed ? transform_uvs(channel.transform, points, transformed) : points,
                    out + size_t(channel.first) * n);
  }
}

// evaluate_material up to the normal map, from the texels of the material's
// lookups (sample_material_textures of `textures`: lookup k's at
// texels[k * stride]) and the vertex colour: every field of `m` but the
// normal. With a normal map, `tangent_normal` gets its tangent-space normal
// (XY scaled, turned into the surface's frame), which evaluate_material turns
// into world space point by point and evaluate_materials (material_batch.h)
// batch-wide.
void evaluate_material_factors(const Material& material, const MaterialTextures& textures, const glm::vec4* texels,
                               int stride, const glm::vec4& color, float emissive_luminance, MaterialSample& m,
                               glm::vec3& tangent_normal);

}  // namespace cr

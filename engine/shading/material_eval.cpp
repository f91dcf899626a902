#include "engine/shading/material_eval.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/safe_normalize.h"
#include "engine/shading/texture_sampler.h"

namespace cr {
namespace {

float saturate(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

// The tangent-space normal (XY scaled) into world space with B = cross(N, T) * w.
glm::vec3 apply_normal_map(const glm::vec3& t, const SurfaceSample& s) {
  const glm::vec3 tangent(s.tangent);
  const glm::vec3 bitangent = glm::cross(s.normal, tangent) * s.tangent.w;
  return normalize_or(tangent * t.x + bitangent * t.y + s.normal * t.z, s.normal);
}

const Sampler& sampler_of(const Scene& scene, const TextureRef& ref) {
  return ref.sampler >= 0 ? scene.samplers[size_t(ref.sampler)] : default_sampler();
}

}  // namespace

const Sampler& default_sampler() {
  static const Sampler sampler{Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::Linear, Filter::Linear};
  return sampler;
}

glm::vec4 sample_material_texture(const Scene& scene, const TextureRef& ref, const SurfaceSample& surface) {
  if (!ref.valid()) return glm::vec4(1.0f);
  const TextureLookup lookup{&scene.images[size_t(ref.image)], &sampler_of(scene, ref)};
  glm::vec4 texel;
  sample_textures(&lookup, 1, surface.uv, surface.duv_dx, surface.duv_dy, &texel);
  return texel;
}

float material_alpha(const Scene& scene, const Material& material, const SurfaceSample& surface) {
  const float texture_alpha = material.base_color.valid() ? sample_material_texture(scene, material.base_color, surface).a : 1.0f;
  return saturate(material.base_color_factor.a * texture_alpha * surface.color.a);
}

MaterialTextures::MaterialTextures(const Scene& scene, const Material& material) {
  // A slot without a texture reads as opaque white, the neutral factor.
  auto use = [&](Slot slot, const TextureRef& ref) {
    lookup_of[slot] = -1;
    if (!ref.valid()) return;
    lookups[count] = {&scene.images[size_t(ref.image)], &sampler_of(scene, ref)};
    lookup_of[slot] = count++;
  };
  use(kBaseColor, material.base_color);
  use(kMetallicRoughness, material.metallic_roughness);
  use(kNormal, material.normal);
  use(kOcclusion, material.occlusion);
  // Emission is skipped altogether when its factor is zero.
  if (material.emissive_factor != glm::vec3(0.0f))
    use(kEmissive, material.emissive);
  else
    lookup_of[kEmissive] = -1;
}

void evaluate_material_factors(const Material& material, const MaterialTextures& textures, const glm::vec4* texels,
                               int stride, const glm::vec4& color, MaterialSample& m, glm::vec3& tangent_normal) {
  using enum MaterialTextures::Slot;
  auto texel = [&](MaterialTextures::Slot slot) {
    return textures.lookup_of[slot] >= 0 ? texels[textures.lookup_of[slot] * stride] : glm::vec4(1.0f);
  };

  const glm::vec4 base = material.base_color_factor * texel(kBaseColor) * color;
  m.base_color = glm::max(glm::vec3(base), glm::vec3(0.0f));
  m.alpha = saturate(base.a);

  const glm::vec4 mr = texel(kMetallicRoughness);
  m.roughness = saturate(material.roughness_factor * mr.g);
  m.metallic = saturate(material.metallic_factor * mr.b);

  if (material.normal.valid()) {
    // glTF: RGB in [0,1] -> [-1,1], XY scaled by normalTexture.scale.
    tangent_normal = glm::vec3(texel(kNormal)) * 2.0f - 1.0f;
    tangent_normal.x *= material.normal.scale;
    tangent_normal.y *= material.normal.scale;
  }

  m.occlusion = 1.0f;
  if (material.occlusion.valid()) {
    const float strength = saturate(material.occlusion.scale);
    m.occlusion = 1.0f + strength * (texel(kOcclusion).r - 1.0f);
  }
  m.emissive = glm::vec3(0.0f);
  if (material.emissive_factor != glm::vec3(0.0f))
    m.emissive = material.emissive_factor * glm::vec3(texel(kEmissive)) * kEmissiveNits;
}

MaterialSample evaluate_material(const Scene& scene, const Material& material, const SurfaceSample& surface) {
  const MaterialTextures textures(scene, material);
  glm::vec4 texels[MaterialTextures::kSlots];
  sample_textures(textures.lookups, textures.count, surface.uv, surface.duv_dx, surface.duv_dy, texels);
  MaterialSample m;
  glm::vec3 tangent_normal(0.0f);
  evaluate_material_factors(material, textures, texels, 1, surface.color, m, tangent_normal);
  m.normal = material.normal.valid() ? apply_normal_map(tangent_normal, surface) : surface.normal;
  return m;
}

}  // namespace cr

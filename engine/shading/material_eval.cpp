#include "engine/shading/material_eval.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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

// Lookups of `t`, set up in slot order, regrouped channel by channel (slot
// order within each): slots differing in UV set or transform read different
// coordinates.
void group_into_channels(MaterialTextures& t, const TextureRef* const* refs) {
  int channel_of[MaterialTextures::kSlots];
  const TextureRef* channel_ref[MaterialTextures::kSlots];  // the first reference of each channel
  t.channel_count = 0;
  for (int s = 0; s < MaterialTextures::kSlots; ++s) {
    channel_of[s] = -1;
    if (t.lookup_of[s] < 0) continue;
    const TextureRef& ref = *refs[s];
    int c = 0;
    while (c < t.channel_count &&
           !(channel_ref[c]->texcoord == ref.texcoord && same_transform(channel_ref[c]->transform, ref.transform)))
      ++c;
    if (c == t.channel_count) {
      channel_ref[c] = &ref;
      t.channels[c] = {ref.texcoord, !ref.transform.identity(), {}, 0, 0};
      if (t.channels[c].transformed) t.channels[c].transform = uv_affine(ref.transform);
      ++t.channel_count;
    }
    ++t.channels[c].count;
    channel_of[s] = c;
  }
  for (int c = 1; c < t.channel_count; ++c) t.channels[c].first = t.channels[c - 1].first + t.channels[c - 1].count;
  TextureLookup in_slot_order[MaterialTextures::kSlots];
  std::copy(t.lookups, t.lookups + t.count, in_slot_order);
  int placed[MaterialTextures::kSlots] = {};
  for (int s = 0; s < MaterialTextures::kSlots; ++s) {
    const int c = channel_of[s];
    if (c < 0) continue;
    const int k = t.channels[c].first + placed[c]++;
    t.lookups[k] = in_slot_order[t.lookup_of[s]];
    t.lookup_of[s] = k;
  }
  const int normal = channel_of[MaterialTextures::kNormal];
  if (normal >= 0 && t.channels[normal].transformed) {
    t.normal_turned = true;
    t.normal_turn = normal_map_turn(t.channels[normal].transform);
  }
}

// Whether a reference reads TEXCOORD_0 untransformed, compared bit for bit
// (cheap, for the many MaterialTextures a frame sets up): a -0.0 offset
// takes the general path, whose texels are the same.
bool plain_coordinates(const TextureRef& ref) {
  static constexpr UvTransform kIdentity{};
  return ref.texcoord == 0 && std::memcmp(&ref.transform, &kIdentity, sizeof(UvTransform)) == 0;
}

// The surface's UV set `texcoord` as one point.
TexturePoints surface_point(const SurfaceSample& s, int texcoord) {
  const glm::vec2& uv = texcoord == 1 ? s.uv1 : s.uv;
  const glm::vec2& dx = texcoord == 1 ? s.duv1_dx : s.duv_dx;
  const glm::vec2& dy = texcoord == 1 ? s.duv1_dy : s.duv_dy;
  return {1, &uv.x, &uv.y, &dx.x, &dx.y, &dy.x, &dy.y};
}

}  // namespace

const Sampler& default_sampler() {
  static const Sampler sampler{Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::Linear, Filter::Linear};
  return sampler;
}

glm::vec4 sample_material_texture(const Scene& scene, const TextureRef& ref, const SurfaceSample& surface) {
  if (!ref.valid()) return glm::vec4(1.0f);
  const TextureLookup lookup{&scene.images[size_t(ref.image)], &sampler_of(scene, ref)};
  const TexturePoints point = surface_point(surface, ref.texcoord);
  glm::vec4 texel;
  if (ref.transform.identity()) {
    sample_textures(&lookup, 1, point, &texel);
  } else {
    TransformedUvs transformed;
    sample_textures(&lookup, 1, transform_uvs(uv_affine(ref.transform), point, transformed), &texel);
  }
  return texel;
}

float material_alpha(const Scene& scene, const Material& material, const SurfaceSample& surface) {
  const float texture_alpha = material.base_color.valid() ? sample_material_texture(scene, material.base_color, surface).a : 1.0f;
  return saturate(material.base_color_factor.a * texture_alpha * surface.color.a);
}

MaterialTextures::MaterialTextures(const Scene& scene, const Material& material) {
  const TextureRef* refs[kSlots] = {&material.base_color, &material.metallic_roughness, &material.normal,
                                    &material.occlusion, &material.emissive};
  // Unlit materials read their base colour alone; emission is skipped
  // altogether when it is zero. A slot without a texture reads as opaque
  // white, the neutral factor.
  bool plain = true;  // every lookup on TEXCOORD_0, untransformed: one channel, the common case
  for (int s = 0; s < kSlots; ++s) {
    lookup_of[s] = -1;
    const TextureRef& ref = *refs[s];
    if (!ref.valid() || (material.unlit && s != kBaseColor) || (s == kEmissive && !emits(material))) continue;
    plain = plain && plain_coordinates(ref);
    lookups[count] = {&scene.images[size_t(ref.image)], &sampler_of(scene, ref)};
    lookup_of[s] = count++;
  }
  if (count == 0) return;
  if (plain) {
    UvChannel& c = channels[0];
    c.texcoord = 0;
    c.transformed = false;
    c.first = 0;
    c.count = count;
    channel_count = 1;
    return;
  }
  group_into_channels(*this, refs);
}

void evaluate_material_factors(const Material& material, const MaterialTextures& textures, const glm::vec4* texels,
                               int stride, const glm::vec4& color, float emissive_luminance, MaterialSample& m,
                               glm::vec3& tangent_normal) {
  using enum MaterialTextures::Slot;
  auto texel = [&](MaterialTextures::Slot slot) {
    return textures.lookup_of[slot] >= 0 ? texels[textures.lookup_of[slot] * stride] : glm::vec4(1.0f);
  };

  const glm::vec4 base = material.base_color_factor * texel(kBaseColor) * color;
  m.base_color = glm::max(glm::vec3(base), glm::vec3(0.0f));
  m.alpha = saturate(base.a);
  if (material.unlit) {
    m.metallic = m.roughness = m.occlusion = 1.0f;
    m.emissive = m.base_color * emissive_luminance;
    m.unlit = true;
    return;
  }
  m.unlit = false;

  const glm::vec4 mr = texel(kMetallicRoughness);
  m.roughness = saturate(material.roughness_factor * mr.g);
  m.metallic = saturate(material.metallic_factor * mr.b);

  if (needs_tangent(material)) {
    // glTF: RGB in [0,1] -> [-1,1], XY scaled by normalTexture.scale.
    tangent_normal = glm::vec3(texel(kNormal)) * 2.0f - 1.0f;
    tangent_normal.x *= material.normal.scale;
    tangent_normal.y *= material.normal.scale;
    if (textures.normal_turned) {
      const float x = tangent_normal.x, y = tangent_normal.y;
      tangent_normal.x = turned_x(textures.normal_turn, x, y);
      tangent_normal.y = turned_y(textures.normal_turn, x, y);
    }
  }

  m.occlusion = 1.0f;
  if (material.occlusion.valid()) {
    const float strength = saturate(material.occlusion.scale);
    m.occlusion = 1.0f + strength * (texel(kOcclusion).r - 1.0f);
  }
  m.emissive = glm::vec3(0.0f);
  if (emits(material)) m.emissive = emissive_scale(material, emissive_luminance) * glm::vec3(texel(kEmissive));
}

MaterialSample evaluate_material(const Scene& scene, const Material& material, const SurfaceSample& surface,
                                 float emissive_luminance) {
  const MaterialTextures textures(scene, material);
  glm::vec4 texels[MaterialTextures::kSlots];
  const TexturePoints uv[2] = {surface_point(surface, 0), surface_point(surface, 1)};
  sample_material_textures(textures, uv, texels);
  MaterialSample m;
  glm::vec3 tangent_normal(0.0f);
  evaluate_material_factors(material, textures, texels, 1, surface.color, emissive_luminance, m, tangent_normal);
  m.normal = needs_tangent(material) ? apply_normal_map(tangent_normal, surface) : surface.normal;
  return m;
}

}  // namespace cr

#include "engine/shading/material_eval.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/safe_normalize.h"
#include "engine/shading/texture_sampler.h"

namespace cr {
namespace {

float saturate(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

// Tangent-space normal map (glTF: RGB in [0,1] -> [-1,1], XY scaled by
// normalTexture.scale) into world space with B = cross(N, T) * w.
glm::vec3 apply_normal_map(const glm::vec3& texel, float scale, const SurfaceSample& s) {
  glm::vec3 t = texel * 2.0f - 1.0f;
  t.x *= scale;
  t.y *= scale;
  const glm::vec3 tangent(s.tangent);
  const glm::vec3 bitangent = glm::cross(s.normal, tangent) * s.tangent.w;
  return normalize_or(tangent * t.x + bitangent * t.y + s.normal * t.z, s.normal);
}

// The texture footprint of the surface point for images of one base size
// read through one sampler: material textures mostly share both, and the
// LOD's log2, the wrapping and the filter weights are a large part of a lookup.
class SharedFootprint {
 public:
  explicit SharedFootprint(const SurfaceSample& surface) : surface_(surface) {}

  const TextureFootprint& of(const Image& image, const Sampler& sampler) {
    const int w = image.mips.empty() ? 0 : image.mips[0].width;
    const int h = image.mips.empty() ? 0 : image.mips[0].height;
    if (w != width_ || h != height_) {
      width_ = w;
      height_ = h;
      sampler_ = nullptr;
      lambda_ = texture_lod(image, surface_.duv_dx, surface_.duv_dy);
    }
    if (&sampler != sampler_) {
      sampler_ = &sampler;
      footprint_ = texture_footprint(image, sampler, surface_.uv, lambda_);
    }
    return footprint_;
  }

 private:
  const SurfaceSample& surface_;
  int width_ = -1;
  int height_ = -1;
  float lambda_ = 0.0f;
  const Sampler* sampler_ = nullptr;
  TextureFootprint footprint_;
};

glm::vec4 sample_slot(const Scene& scene, const TextureRef& ref, SharedFootprint& footprint) {
  if (!ref.valid()) return glm::vec4(1.0f);
  const Image& image = scene.images[size_t(ref.image)];
  const Sampler& sampler = ref.sampler >= 0 ? scene.samplers[size_t(ref.sampler)] : default_sampler();
  return sample_footprint(image, footprint.of(image, sampler));
}

}  // namespace

const Sampler& default_sampler() {
  static const Sampler sampler{Wrap::Repeat, Wrap::Repeat, Filter::Linear, Filter::Linear, Filter::Linear};
  return sampler;
}

glm::vec4 sample_material_texture(const Scene& scene, const TextureRef& ref, const SurfaceSample& surface) {
  SharedFootprint footprint(surface);
  return sample_slot(scene, ref, footprint);
}

float material_alpha(const Scene& scene, const Material& material, const SurfaceSample& surface) {
  const float texture_alpha = material.base_color.valid() ? sample_material_texture(scene, material.base_color, surface).a : 1.0f;
  return saturate(material.base_color_factor.a * texture_alpha * surface.color.a);
}

MaterialSample evaluate_material(const Scene& scene, const Material& material, const SurfaceSample& surface) {
  SharedFootprint footprint(surface);
  MaterialSample m;
  const glm::vec4 base = material.base_color_factor * sample_slot(scene, material.base_color, footprint) * surface.color;
  m.base_color = glm::max(glm::vec3(base), glm::vec3(0.0f));
  m.alpha = saturate(base.a);

  const glm::vec4 mr = sample_slot(scene, material.metallic_roughness, footprint);
  m.roughness = saturate(material.roughness_factor * mr.g);
  m.metallic = saturate(material.metallic_factor * mr.b);

  m.normal = material.normal.valid()
                 ? apply_normal_map(glm::vec3(sample_slot(scene, material.normal, footprint)),
                                    material.normal.scale, surface)
                 : surface.normal;

  if (material.occlusion.valid()) {
    const float strength = saturate(material.occlusion.scale);
    m.occlusion = 1.0f + strength * (sample_slot(scene, material.occlusion, footprint).r - 1.0f);
  }
  if (material.emissive_factor != glm::vec3(0.0f)) {
    m.emissive = material.emissive_factor * glm::vec3(sample_slot(scene, material.emissive, footprint)) *
                 kEmissiveNits;
  }
  return m;
}

}  // namespace cr

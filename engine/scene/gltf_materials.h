#pragma once
// glTF samplers, materials and the images they use, converted and validated.
// Material extensions read: KHR_texture_transform (per texture reference,
// with its texCoord override), KHR_materials_emissive_strength and
// KHR_materials_unlit. Texture references read TEXCOORD_0 or TEXCOORD_1; a
// higher set falls back to TEXCOORD_0 with a warning.
#include <vector>

#include "engine/scene/gltf_context.h"
#include "engine/scene/gltf_image_decoding.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene.h"

namespace cr {

struct GltfMaterials {
  std::vector<Sampler> samplers;    // same indices as the glTF samplers
  std::vector<Material> materials;  // same indices as the glTF materials
  std::vector<Image> images;        // one per (glTF image, colour space) used by a material
};

// Throws InputError for invalid values or references, for images that could
// not be decoded, and for missing image files unless options allow them.
GltfMaterials load_materials(const GltfContext& ctx, const ImageDecodeLog& decode_log,
                             const GltfLoadOptions& options);

}  // namespace cr

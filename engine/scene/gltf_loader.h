#pragma once
// glTF 2.0 loading (.gltf with external or data-URI buffers, and .glb) into a
// validated Scene. Every malformed input is rejected with one InputError naming
// the file and what is wrong; nothing is rendered from a half-checked file.
//
// What is loaded: the default scene (or scene 0; with no scenes, every root
// node), node transforms, triangle primitives (strips and fans converted to
// lists; points and lines skipped), PBR metallic-roughness materials, samplers,
// images with full mip chains, perspective cameras and a KHR_lights_punctual
// directional light as the sun. Scene::cameras lists the perspective cameras
// in scene traversal order (depth first, children in file order); a scene
// file's "gltf_camera": N indexes that list.
//
// Documented fallbacks (each prints a warning to stderr):
// - texCoord != 0 in a texture reference: TEXCOORD_0 is used instead;
// - zero-length or non-finite normals/tangents: replaced by generated ones;
// - unused features (skins, morph targets, animations, orthographic cameras,
//   point/spot lights, non-required extensions) are ignored.
#include <string>

#include "engine/scene/scene.h"

namespace cr {

struct GltfLoadOptions {
  // Load even when image files are missing: textures that use them are dropped
  // (their material falls back to its factors) and a warning names each one.
  bool allow_missing_images = false;
  // Bytes of linear-float texture copies (image_texels.h) the loader may add:
  // images in file order are decoded while they fit, the rest stay RGBA8.
  size_t texture_decode_budget = size_t(512) << 20;
};

Scene load_gltf(const std::string& path, const GltfLoadOptions& options = {});

}  // namespace cr

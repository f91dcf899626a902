#pragma once
// glTF 2.0 loading (.gltf with external or data-URI buffers, and .glb) into a
// validated Scene. Every malformed input is rejected with one InputError naming
// the file and what is wrong; nothing is rendered from a half-checked file.
//
// What is loaded (docs/scene.md has the full table): the default
// scene (or scene 0; with no scenes, every root node), node transforms,
// triangle primitives (strips and fans converted to lists; points and lines
// skipped), sparse, quantized (KHR_mesh_quantization), Draco and meshopt
// compressed geometry, PBR metallic-roughness materials with texture
// transforms, two UV sets, unlit and emissive strength, samplers, images with
// full mip chains, perspective and orthographic cameras, KHR_lights_punctual
// lights (the first directional one as the sun), EXT_mesh_gpu_instancing,
// morph targets, skins and animations (kept in Scene::animation to pose the
// scene at a time: scene_animation.h; loaded at the rest pose).
// Scene::cameras lists the cameras in scene traversal order (depth first,
// children in file order); a scene file's "gltf_camera": N indexes that list.
//
// Every fallback prints one warning per file to stderr (generated normals
// and tangents, unsupported extensions that are not required, ...).
#include <string>

#include "engine/core/memory_budget.h"
#include "engine/scene/scene.h"

namespace cr {

struct GltfLoadOptions {
  // Load even when image files are missing: textures that use them are dropped
  // (their material falls back to its factors) and a warning names each one.
  bool allow_missing_images = false;
  // Let URIs name files outside the model's folder and its subfolders
  // (refused by default: a model file must not read arbitrary files).
  bool allow_outside_paths = false;
  // Bytes the decoded images may take, RGBA8 with their mip chains (the
  // profile's texture_decode_budget_mb). When the chains exceed it, the
  // largest chain drops its top level, again until all fit (or are 1x1),
  // like a GPU texture pool's mip bias; a warning names each image dropped
  // and the size it loads at.
  size_t texture_decode_budget = size_t(512) << 20;
  // When set, what the load holds is charged to it: the parsed JSON (checked
  // while parsing), buffers and decoded images before they are allocated,
  // the geometry once built. A model that needs more than its limit is
  // refused with an InputError naming the field ("images[3]").
  MemoryBudget* memory = nullptr;
};

Scene load_gltf(const std::string& path, const GltfLoadOptions& options = {});

}  // namespace cr

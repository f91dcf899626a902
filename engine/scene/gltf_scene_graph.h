#pragma once
// The glTF node hierarchy: validated (indices, transforms, one parent per node,
// no cycles) with what its nodes place (meshes and their instances, skins,
// morph weights, cameras, KHR_lights_punctual lights) and the file's
// animations, then posed at rest into draws, cameras, lights and the sun.
#include "engine/scene/gltf_context.h"
#include "engine/scene/gltf_meshes.h"
#include "engine/scene/scene.h"

namespace cr {

// Fills scene.draws, cameras (perspective and orthographic, in traversal
// order: depth first, children in file order), lights, sun, bounds_* and,
// when the file has animations, scene.animation; appends to scene.meshes a
// posed copy of the mesh of every node that morphs or skins it. scene.meshes
// must already hold `meshes.meshes`; `meshes.deformations` is taken.
void place_nodes(const GltfContext& ctx, GltfMeshes& meshes, Scene& scene);

}  // namespace cr

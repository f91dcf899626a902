#pragma once
// The glTF node hierarchy: validated (indices, transforms, one parent per node,
// no cycles) and flattened into draws, cameras and the sun.
#include "engine/scene/gltf_context.h"
#include "engine/scene/gltf_meshes.h"
#include "engine/scene/scene.h"

namespace cr {

// Fills scene.draws, scene.cameras, scene.sun and scene.bounds_*; scene.meshes
// must already hold `meshes.meshes`.
void place_nodes(const GltfContext& ctx, const GltfMeshes& meshes, Scene& scene);

}  // namespace cr

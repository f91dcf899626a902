#pragma once
// glTF meshes to triangle-list primitives with complete vertex streams.
#include <vector>

#include "engine/scene/gltf_context.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_animation.h"

namespace cr {

struct GltfMeshes {
  std::vector<Mesh> meshes;  // same indices as the glTF meshes
  // primitive_index[mesh][glTF primitive] = index in meshes[mesh].primitives,
  // or -1 for a primitive that is not rendered (points, lines, no POSITION).
  std::vector<std::vector<int>> primitive_index;
  // Morph targets and skin influences per mesh, one entry per primitive of
  // meshes[mesh] (empty for a primitive nothing deforms).
  std::vector<MeshDeformation> deformations;
};

// `materials` are the already converted materials: they decide whether
// tangents are needed (normal map) and whether TEXCOORD_0 is required.
GltfMeshes load_meshes(const GltfContext& ctx, const std::vector<Material>& materials);

}  // namespace cr

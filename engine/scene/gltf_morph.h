#pragma once
// glTF morph targets: per-primitive POSITION/NORMAL/TANGENT deltas and the
// weights that blend them (mesh defaults, overridden per node).
#include <string>
#include <vector>

#include "engine/scene/gltf_context.h"
#include "engine/scene/scene_animation.h"

namespace cr {

struct MorphTargets {
  std::vector<MorphTarget> targets;
  size_t ignored_attributes = 0;  // TEXCOORD_n/COLOR_n deltas, not applied
};

// The targets of one primitive with `vertex_count` vertices: each delta
// accessor VEC3 with one finite value per vertex. `label` names the
// primitive in messages.
MorphTargets load_morph_targets(const GltfContext& ctx, const tinygltf::Primitive& primitive, size_t vertex_count,
                                const std::string& label);

// The number of morph targets of mesh `mesh`: equal for all its primitives,
// and the size of its "weights" when given (finite values). The accessors of
// every primitive's targets are checked, drawn or not.
size_t mesh_target_count(const GltfContext& ctx, size_t mesh);

// The rest weights of node `node` drawing a mesh with `target_count`
// targets: the node's "weights", else the mesh's, else zeros; checked for
// count and finiteness.
std::vector<float> rest_morph_weights(const GltfContext& ctx, size_t node, size_t target_count);

}  // namespace cr

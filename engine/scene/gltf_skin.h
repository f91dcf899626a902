#pragma once
// glTF skins: the joints and inverse bind matrices of each skin, and the
// per-vertex joint influences (JOINTS_n/WEIGHTS_n) of a primitive.
#include <string>
#include <vector>

#include "engine/scene/gltf_context.h"
#include "engine/scene/scene_animation.h"

namespace cr {

// Reads the primitive's JOINTS_n/WEIGHTS_n sets (n = 0, 1, ... while both
// exist) into deformation.joints/weights/max_joint: VEC4 each, one per
// vertex, weights finite, non-negative and summing to 1 over all sets
// (within 2%, then normalised). JOINTS_n without WEIGHTS_n, or the other
// way round, is an error.
void load_skin_influences(const GltfContext& ctx, const tinygltf::Primitive& primitive, size_t vertex_count,
                          const std::string& label, PrimitiveDeformation& deformation);

// The file's skins: joints in range and distinct, inverse bind matrices
// (float MAT4, at least one per joint, finite; identity without the
// accessor). `parent` is each node's parent (-1 for roots); a skeleton that
// is not a common root of the joints is warned about (it does not change
// the pose).
std::vector<SceneSkin> load_skins(const GltfContext& ctx, const std::vector<int>& parent);

}  // namespace cr

#pragma once
// glTF animations: channels that drive node translation, rotation, scale or
// morph weights through keyframe samplers.
#include <vector>

#include "engine/scene/gltf_context.h"
#include "engine/scene/scene_animation.h"

namespace cr {

// The file's animations, checked: samplers and target nodes in range, one
// channel per (node, path) in an animation, no channel on a node given by
// "matrix", weights only on nodes whose mesh has morph targets; input times
// finite, >= 0 and strictly increasing; outputs of the path's type, finite,
// one per key (three per key for CUBICSPLINE; times the target count for
// weights), rotations non-zero (normalised). Channels with a path other than
// the four (left to extensions) are ignored with one warning. `nodes` must hold the rest transforms and meshes, and
// `deformations` the morph target counts.
std::vector<AnimationClip> load_animations(const GltfContext& ctx, const std::vector<SceneNode>& nodes,
                                           const std::vector<MeshDeformation>& deformations);

}  // namespace cr

#pragma once
// A primitive's posed shape on the CPU: morph targets blended by weights
// (position = rest + sum of weight * delta, normals and tangents likewise,
// then renormalised), then linear blend skinning (each vertex moved by the
// weighted sum of its joints' matrices, normals by that sum's
// inverse-transpose, tangents by the sum itself). Primitives without
// NORMAL/TANGENT in the file get theirs generated again from the posed
// positions, as at load.
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/scene/scene_animation.h"

namespace cr {

// Rewrites out.positions, normals, tangents and bounds; `out` must be a
// copy of `rest` (same vertices, indices and UVs). `weights` has one value
// per morph target of `deformation`; `joint_matrices` (joint world matrix
// times inverse bind matrix, per skin joint) is empty for an unskinned pose,
// which leaves the result in the mesh's own space.
void deform_primitive(const Primitive& rest, const PrimitiveDeformation& deformation,
                      const std::vector<float>& weights, const std::vector<glm::dmat4>& joint_matrices,
                      Primitive& out);

}  // namespace cr

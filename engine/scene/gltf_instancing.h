#pragma once
// EXT_mesh_gpu_instancing: a mesh node drawn once per instance, each placed
// by node world * T * R * S of the instance's TRANSLATION, ROTATION, SCALE.
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/gltf_context.h"

namespace cr {

// The node's instance transforms; empty when it has no EXT_mesh_gpu_instancing.
// Checked: "attributes" a non-empty object of accessor indices; TRANSLATION and SCALE
// float VEC3, ROTATION float or normalized BYTE/SHORT VEC4 (non-zero, then
// normalised); every attribute (custom "_NAME" ones too) of the same count;
// finite values. Other attribute names are errors.
std::vector<glm::dmat4> load_instances(const GltfContext& ctx, size_t node);

}  // namespace cr

#pragma once
// KHR_draco_mesh_compression, decoded before meshes are read: each primitive
// carrying the extension has its Draco bufferView decoded (Debian's
// libdraco), and its indices and the attributes the extension names are
// written to new buffers, bufferViews and accessors of the model. The
// primitive is repointed at those accessors, so the rest of the loader reads
// it as a plain primitive. The file's own accessors (count, type and
// componentType, no data) are checked against the decoded data and left
// untouched: an accessor shared with another primitive is never overwritten.
#include <tiny_gltf.h>

#include "engine/scene/gltf_context.h"

namespace cr {

// `model` is ctx.model, writable. Throws InputError for data that does not
// decode or does not match the accessors the file declares.
void decode_draco_primitives(const GltfContext& ctx, tinygltf::Model& model);

}  // namespace cr

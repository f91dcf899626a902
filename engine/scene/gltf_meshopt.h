#pragma once
// EXT_meshopt_compression in two steps around tinygltf's parse.
//
// Before, on the JSON: each bufferView's extension object is checked (field
// types, which tinygltf would silently truncate, and the layout rules of the
// extension: byteStride, count and byteLength as the decoder needs them).
// Fallback buffers ("fallback": true, often without uri or data, never read
// by a loader that decodes the extension) are replaced by a one-byte
// placeholder, so tinygltf neither fails on them nor reads them; a reference
// to one from anything but a compressed bufferView is rejected there, before
// it could read the placeholder.
//
// After, on the model: each compressed bufferView is decoded (Debian's
// libmeshoptimizer: modes ATTRIBUTES, TRIANGLES, INDICES; filters NONE,
// OCTAHEDRAL, QUATERNION, EXPONENTIAL) into a new buffer, and the bufferView
// is repointed at it, so accessors read it as plain data.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "engine/scene/gltf_context.h"

namespace cr {

enum class MeshoptMode { Attributes, Triangles, Indices };
enum class MeshoptFilter { None, Octahedral, Quaternion, Exponential };

// A bufferView's extension object, checked against the extension's rules.
struct MeshoptView {
  int buffer_view = 0;  // the bufferView carrying the extension
  int buffer = 0;       // where the compressed bytes are
  uint64_t byte_offset = 0;
  uint64_t byte_length = 0;
  uint64_t byte_stride = 0;
  uint64_t count = 0;   // elements of byte_stride bytes after decoding
  MeshoptMode mode = MeshoptMode::Attributes;
  MeshoptFilter filter = MeshoptFilter::None;
};

struct MeshoptDocument {
  std::vector<MeshoptView> views;
  bool fallback_replaced = false;  // `doc` changed: tinygltf must parse the edited JSON
};

// Throws InputError(path, ...) naming the bufferView and field at fault.
MeshoptDocument prepare_meshopt_compression(const std::string& path, nlohmann::json& doc);

// `model` is ctx.model, writable; `views` come from prepare_meshopt_compression
// on its JSON. Throws InputError for compressed bytes outside their buffer or
// data that does not decode.
void decode_meshopt_buffer_views(const GltfContext& ctx, tinygltf::Model& model, const std::vector<MeshoptView>& views);

}  // namespace cr

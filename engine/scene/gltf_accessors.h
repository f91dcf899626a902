#pragma once
// Validated reading of glTF accessors. Before a byte is read, the accessor, its
// bufferView and buffer are checked: indices in range, component type and
// element type allowed for the use, count within limits, and the last element
// (offset + (count-1)*stride + element size) inside the bufferView, which
// itself must lie inside its buffer. Sparse accessors are rejected.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "engine/scene/gltf_context.h"

namespace cr {

// Largest element count accepted for one accessor (2^28): larger is taken as
// a corrupt or hostile file rather than a scene this renderer can hold.
constexpr size_t kMaxAccessorCount = size_t(1) << 28;

// Values of a float attribute, `components` floats per element.
struct FloatAccessor {
  std::vector<float> values;
  int components = 0;
  size_t count = 0;
};

// What an accessor holds: decides which component types are allowed (core
// glTF 2.0 plus KHR_mesh_quantization) and how integers become floats
// (normalized: the spec's unorm/snorm rules; otherwise the integer value).
enum class AttributeKind {
  Position,    // POSITION
  Normal,      // NORMAL
  Tangent,     // TANGENT
  Texcoord,    // TEXCOORD_n
  Color,       // COLOR_n
  Weights,     // WEIGHTS_n
  MorphDelta,  // POSITION/NORMAL/TANGENT of a morph target
  Scalar,      // float-only data: inverse bind matrices, animation times and values, instance transforms
};

// Reads a float attribute. `types` lists the allowed TINYGLTF_TYPE_* values;
// `kind` the allowed component types. `what` names the use in messages
// ("POSITION of mesh 0 primitive 1").
FloatAccessor read_float_accessor(const GltfContext& ctx, int accessor, const std::string& what,
                                  std::initializer_list<int> types, AttributeKind kind);

// Reads a SCALAR unsigned byte/short/int index accessor.
std::vector<uint32_t> read_index_accessor(const GltfContext& ctx, int accessor, const std::string& what);

// Checks an accessor's bounds without reading it (for attributes the renderer
// does not use) and returns its element count.
size_t check_accessor(const GltfContext& ctx, int accessor, const std::string& what);

}  // namespace cr

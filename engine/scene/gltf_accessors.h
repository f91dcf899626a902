#pragma once
// Validated reading of glTF accessors. Before a byte is read, the accessor, its
// bufferView and buffer are checked: indices in range, component type and
// element type allowed for the use, count within limits, and the last element
// (offset + (count-1)*stride + element size) inside the bufferView, which
// itself must lie inside its buffer. An accessor without bufferView reads as
// zeros (glTF 2.0); a sparse accessor's substitutes are checked the same way
// (count, strictly increasing indices below the accessor's count, index and
// value ranges inside their views) and applied by every reader here.
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include <glm/ext/vector_uint4_sized.hpp>

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
  AnimatedRotationOrWeights,  // animation outputs of rotations and morph weights
  Scalar,      // float-only data: inverse bind matrices, animation times and other outputs, instance transforms
};

// Reads a float attribute. `types` lists the allowed TINYGLTF_TYPE_* values;
// `kind` the allowed component types. `what` names the use in messages
// ("POSITION of mesh 0 primitive 1").
FloatAccessor read_float_accessor(const GltfContext& ctx, int accessor, const std::string& what,
                                  std::initializer_list<int> types, AttributeKind kind);

// Reads a SCALAR unsigned byte/short/int index accessor.
std::vector<uint32_t> read_index_accessor(const GltfContext& ctx, int accessor, const std::string& what);

// Reads a JOINTS_n accessor: VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT, not
// normalized (the values are joint indices of the node's skin).
std::vector<glm::u16vec4> read_joints_accessor(const GltfContext& ctx, int accessor, const std::string& what);

// Checks an accessor's bounds without reading it (for attributes the renderer
// does not use) and returns its element count.
size_t check_accessor(const GltfContext& ctx, int accessor, const std::string& what);

// The bytes [offset, offset + length) of buffer `buffer`, after checking the
// buffer exists and holds them; `label` names the user in messages. Valid
// until the model's buffers change.
std::span<const uint8_t> gltf_buffer_bytes(const GltfContext& ctx, const std::string& label, int buffer,
                                           uint64_t offset, uint64_t length);

// The bytes of bufferView `view`, after checking it exists and lies inside
// its buffer.
std::span<const uint8_t> gltf_buffer_view_bytes(const GltfContext& ctx, const std::string& label, int view);

// Size in bytes of a TINYGLTF_COMPONENT_TYPE_* (0 for an invalid one) and the
// component count of a TINYGLTF_TYPE_* (0 for an invalid one), with their
// names for messages; the Draco decoder (gltf_draco) needs them too.
int gltf_component_size(int component_type);
int gltf_component_count(int type);
std::string gltf_component_type_name(int component_type);
std::string gltf_type_name(int type);

}  // namespace cr

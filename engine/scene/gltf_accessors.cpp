#include "engine/scene/gltf_accessors.h"

#include <algorithm>
#include <cstring>

namespace cr {

namespace {

// The largest element: a MAT4 of floats.
constexpr size_t kMaxElementBytes = 64;
constexpr uint8_t kZeroElement[kMaxElementBytes] = {};

// Elements of an accessor without bufferView cost nothing in the file, so
// their expanded size is capped (256 MiB) where a dense accessor is capped by
// the file's own size.
constexpr uint64_t kMaxZeroAccessorBytes = uint64_t(1) << 28;

// A validated accessor. element(i) points at the bytes of element i: a sparse
// substitute, the base bufferView's element, or zeros without a bufferView.
struct AccessorElements {
  size_t count = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;
  size_t element_size = 0;
  const uint8_t* base = nullptr;  // null: no bufferView
  size_t stride = 0;
  std::vector<uint32_t> sparse_indices;  // strictly increasing
  const uint8_t* sparse_values = nullptr;

  const uint8_t* element(size_t i) const {
    if (!sparse_indices.empty()) {
      auto it = std::lower_bound(sparse_indices.begin(), sparse_indices.end(), i);
      if (it != sparse_indices.end() && *it == i) {
        return sparse_values + static_cast<size_t>(it - sparse_indices.begin()) * element_size;
      }
    }
    return base ? base + i * stride : kZeroElement;
  }
};

template <typename T>
T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// The bufferView `index`, checked to lie inside its buffer. `label` names
// its user in messages.
const tinygltf::BufferView& checked_view(const GltfContext& ctx, const std::string& label, int index) {
  const tinygltf::Model& m = ctx.model;
  if (index < 0 || static_cast<size_t>(index) >= m.bufferViews.size()) {
    ctx.fail(label + " has bufferView " + std::to_string(index) + " out of range (" +
             std::to_string(m.bufferViews.size()) + " bufferViews)");
  }
  const tinygltf::BufferView& bv = m.bufferViews[index];
  gltf_buffer_bytes(ctx, label + ": bufferView " + std::to_string(index), bv.buffer, bv.byteOffset, bv.byteLength);
  return bv;
}

// The `needed` bytes at `offset` in bufferView `index`, after checking they
// lie inside it. `layout` says what needs them ("byteOffset 0, count 3, stride 12").
const uint8_t* view_bytes(const GltfContext& ctx, const std::string& label, int index, uint64_t offset,
                          uint64_t needed, const std::string& layout) {
  const std::span<const uint8_t> view = gltf_buffer_view_bytes(ctx, label, index);
  if (offset > view.size() || needed > view.size() - offset) {
    ctx.fail(label + " (" + layout + ") needs " + std::to_string(offset + needed) + " bytes but bufferView " +
             std::to_string(index) + " has " + std::to_string(view.size()));
  }
  return view.data() + offset;
}

// Reads and checks the sparse substitutes of accessor `a` into `e`.
void read_sparse(const GltfContext& ctx, const std::string& label, const tinygltf::Accessor& a, AccessorElements& e) {
  const auto& s = a.sparse;
  const std::string sparse = label + " sparse";
  if (s.count < 1 || static_cast<size_t>(s.count) > a.count) {
    ctx.fail(sparse + ".count " + std::to_string(s.count) + " must be in [1, " + std::to_string(a.count) +
             "] (the accessor's count)");
  }
  const int ct = s.indices.componentType;
  if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    ctx.fail(sparse + ".indices has component type " + gltf_component_type_name(ct) +
             "; expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  if (s.indices.byteOffset < 0 || s.values.byteOffset < 0) ctx.fail(sparse + " has a negative byteOffset");
  const size_t n = static_cast<size_t>(s.count);
  const size_t isize = static_cast<size_t>(gltf_component_size(ct));
  const uint8_t* idx = view_bytes(ctx, sparse + ".indices", s.indices.bufferView, static_cast<uint64_t>(s.indices.byteOffset),
                                  n * isize, "byteOffset " + std::to_string(s.indices.byteOffset) + ", count " +
                                                 std::to_string(n) + ", " + gltf_component_type_name(ct));
  e.sparse_indices.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const uint8_t* p = idx + k * isize;
    const uint32_t v = isize == 1 ? p[0] : isize == 2 ? load<uint16_t>(p) : load<uint32_t>(p);
    if (v >= a.count) {
      ctx.fail(sparse + ".indices[" + std::to_string(k) + "] = " + std::to_string(v) + " is out of range for count " +
               std::to_string(a.count));
    }
    if (k > 0 && v <= e.sparse_indices[k - 1]) {
      ctx.fail(sparse + ".indices[" + std::to_string(k) + "] = " + std::to_string(v) + " does not follow " +
               std::to_string(e.sparse_indices[k - 1]) + " (indices must be strictly increasing)");
    }
    e.sparse_indices[k] = v;
  }
  e.sparse_values = view_bytes(ctx, sparse + ".values", s.values.bufferView, static_cast<uint64_t>(s.values.byteOffset),
                               n * e.element_size, "byteOffset " + std::to_string(s.values.byteOffset) + ", count " +
                                                       std::to_string(n) + ", " + std::to_string(e.element_size) +
                                                       "-byte elements");
}

AccessorElements view_accessor(const GltfContext& ctx, int index, const std::string& what) {
  const tinygltf::Model& m = ctx.model;
  if (index < 0 || static_cast<size_t>(index) >= m.accessors.size()) {
    ctx.fail(what + ": accessor index " + std::to_string(index) + " out of range (" +
             std::to_string(m.accessors.size()) + " accessors)");
  }
  const tinygltf::Accessor& a = m.accessors[index];
  const std::string label = what + ": accessor " + std::to_string(index);
  const int csize = gltf_component_size(a.componentType);
  const int ncomp = gltf_component_count(a.type);
  if (csize == 0) ctx.fail(label + " has invalid componentType " + std::to_string(a.componentType));
  if (ncomp == 0) ctx.fail(label + " has invalid type " + std::to_string(a.type));
  if (a.count < 1) ctx.fail(label + " has count 0 (must be at least 1)");
  if (a.count > kMaxAccessorCount) {
    ctx.fail(label + " has count " + std::to_string(a.count) + ", above the limit of " +
             std::to_string(kMaxAccessorCount));
  }
  AccessorElements out;
  out.count = a.count;
  out.component_type = a.componentType;
  out.components = ncomp;
  out.normalized = a.normalized;
  out.element_size = static_cast<size_t>(csize) * static_cast<size_t>(ncomp);
  if (a.bufferView == -1) {
    if (static_cast<uint64_t>(a.count) * out.element_size > kMaxZeroAccessorBytes) {
      ctx.fail(label + " has no bufferView and count " + std::to_string(a.count) + ": its " +
               std::to_string(a.count * out.element_size) + " bytes of zeros are above the limit of " +
               std::to_string(kMaxZeroAccessorBytes));
    }
  } else {
    const tinygltf::BufferView& bv = checked_view(ctx, label, a.bufferView);
    out.stride = out.element_size;
    if (bv.byteStride != 0) {
      if (bv.byteStride < out.element_size || bv.byteStride > 252) {
        ctx.fail(label + ": bufferView " + std::to_string(a.bufferView) + " byteStride " +
                 std::to_string(bv.byteStride) + " must be in [" + std::to_string(out.element_size) + ", 252] for " +
                 gltf_type_name(a.type) + " " + gltf_component_type_name(a.componentType));
      }
      out.stride = bv.byteStride;
    }
    // count <= 2^28 and stride <= 252, so the product cannot overflow 64 bits.
    const uint64_t needed = static_cast<uint64_t>(a.count - 1) * out.stride + out.element_size;
    out.base = view_bytes(ctx, label, a.bufferView, a.byteOffset, needed,
                          "byteOffset " + std::to_string(a.byteOffset) + ", count " + std::to_string(a.count) +
                              ", stride " + std::to_string(out.stride));
  }
  if (a.sparse.isSparse) read_sparse(ctx, label, a, out);
  return out;
}

// An integer component type a kind accepts besides FLOAT.
struct IntegerComponent {
  int component_type;
  bool must_be_normalized;  // false: normalized or not
};

// Core glTF 2.0 allows, besides FLOAT: TEXCOORD_n, COLOR_n and WEIGHTS_n as
// normalized UNSIGNED_BYTE/UNSIGNED_SHORT; POSITION, NORMAL, TANGENT and
// their morph deltas as FLOAT only. KHR_mesh_quantization adds POSITION and
// TEXCOORD_n as (UNSIGNED_)BYTE/(UNSIGNED_)SHORT normalized or not, NORMAL
// and TANGENT as normalized BYTE/SHORT, morph deltas as BYTE/SHORT. These
// are read without the extension declared too: the data is unambiguous.
// Animation outputs of rotations and weights may be FLOAT or any normalized
// (UNSIGNED_)BYTE/(UNSIGNED_)SHORT (core glTF; gltfpack writes them so).
std::span<const IntegerComponent> integer_components(AttributeKind kind) {
  using C = IntegerComponent;
  static constexpr C kAnyInteger[] = {{TINYGLTF_COMPONENT_TYPE_BYTE, false},
                                      {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, false},
                                      {TINYGLTF_COMPONENT_TYPE_SHORT, false},
                                      {TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, false}};
  static constexpr C kSignedNormalized[] = {{TINYGLTF_COMPONENT_TYPE_BYTE, true}, {TINYGLTF_COMPONENT_TYPE_SHORT, true}};
  static constexpr C kUnsignedNormalized[] = {{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, true},
                                              {TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, true}};
  static constexpr C kAnyNormalized[] = {{TINYGLTF_COMPONENT_TYPE_BYTE, true},
                                        {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, true},
                                        {TINYGLTF_COMPONENT_TYPE_SHORT, true},
                                        {TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, true}};
  static constexpr C kSigned[] = {{TINYGLTF_COMPONENT_TYPE_BYTE, false}, {TINYGLTF_COMPONENT_TYPE_SHORT, false}};
  switch (kind) {
    case AttributeKind::Position:
    case AttributeKind::Texcoord: return kAnyInteger;
    case AttributeKind::Normal:
    case AttributeKind::Tangent: return kSignedNormalized;
    case AttributeKind::Color:
    case AttributeKind::Weights: return kUnsignedNormalized;
    case AttributeKind::MorphDelta: return kSigned;
    case AttributeKind::AnimatedRotationOrWeights: return kAnyNormalized;
    case AttributeKind::Scalar: return {};
  }
  return {};
}

bool component_allowed(AttributeKind kind, int component_type, bool normalized) {
  if (component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) return true;
  for (const IntegerComponent& c : integer_components(kind)) {
    if (c.component_type == component_type && (normalized || !c.must_be_normalized)) return true;
  }
  return false;
}

std::string allowed_components(AttributeKind kind) {
  std::string s = "FLOAT";
  for (const IntegerComponent& c : integer_components(kind)) {
    s += ", " + std::string(c.must_be_normalized ? "normalized " : "") + gltf_component_type_name(c.component_type) +
         (c.must_be_normalized ? "" : " (normalized or not)");
  }
  return s;
}

// glTF's conversion of one component: unorm c/(2^n-1), snorm max(c/(2^(n-1)-1), -1),
// integers that are not normalized as their value.
float component_value(const uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float c = p[0];
      return normalized ? c / 255.0f : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float c = load<uint16_t>(p);
      return normalized ? c / 65535.0f : c;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float c = load<int8_t>(p);
      return normalized ? std::max(c / 127.0f, -1.0f) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float c = load<int16_t>(p);
      return normalized ? std::max(c / 32767.0f, -1.0f) : c;
    }
    default: return load<float>(p);
  }
}

}  // namespace

std::span<const uint8_t> gltf_buffer_bytes(const GltfContext& ctx, const std::string& label, int buffer,
                                           uint64_t offset, uint64_t length) {
  const tinygltf::Model& m = ctx.model;
  if (buffer < 0 || static_cast<size_t>(buffer) >= m.buffers.size()) {
    ctx.fail(label + " has buffer " + std::to_string(buffer) + " out of range (" + std::to_string(m.buffers.size()) +
             " buffers)");
  }
  const std::vector<unsigned char>& data = m.buffers[buffer].data;
  if (offset > data.size() || length > data.size() - offset) {
    ctx.fail(label + " (byteOffset " + std::to_string(offset) + ", byteLength " + std::to_string(length) +
             ") extends past the end of buffer " + std::to_string(buffer) + " (" + std::to_string(data.size()) +
             " bytes)");
  }
  return {data.data() + offset, static_cast<size_t>(length)};
}

std::span<const uint8_t> gltf_buffer_view_bytes(const GltfContext& ctx, const std::string& label, int view) {
  const tinygltf::BufferView& bv = checked_view(ctx, label, view);
  return {ctx.model.buffers[bv.buffer].data.data() + bv.byteOffset, bv.byteLength};
}

int gltf_component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int gltf_component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

std::string gltf_type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "type " + std::to_string(type);
  }
}

std::string gltf_component_type_name(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return "component type " + std::to_string(component_type);
  }
}

size_t check_accessor(const GltfContext& ctx, int accessor, const std::string& what) {
  return view_accessor(ctx, accessor, what).count;
}

FloatAccessor read_float_accessor(const GltfContext& ctx, int accessor, const std::string& what,
                                  std::initializer_list<int> types, AttributeKind kind) {
  const AccessorElements b = view_accessor(ctx, accessor, what);
  const tinygltf::Accessor& a = ctx.model.accessors[accessor];
  bool type_ok = false;
  std::string allowed;
  for (int t : types) {
    type_ok = type_ok || t == a.type;
    allowed += (allowed.empty() ? "" : " or ") + gltf_type_name(t);
  }
  const std::string label = what + ": accessor " + std::to_string(accessor);
  if (!type_ok) ctx.fail(label + " has type " + gltf_type_name(a.type) + "; expected " + allowed);
  if (!component_allowed(kind, b.component_type, b.normalized)) {
    const bool is_float = b.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    ctx.fail(label + " has component type " + gltf_component_type_name(b.component_type) +
             (is_float ? "" : b.normalized ? " (normalized)" : " (not normalized)") + "; expected " +
             allowed_components(kind));
  }
  const size_t csize = static_cast<size_t>(gltf_component_size(b.component_type));
  FloatAccessor out;
  out.components = b.components;
  out.count = b.count;
  out.values.resize(b.count * static_cast<size_t>(b.components));
  for (size_t i = 0; i < b.count; ++i) {
    const uint8_t* e = b.element(i);
    for (int c = 0; c < b.components; ++c) {
      out.values[i * b.components + c] = component_value(e + c * csize, b.component_type, b.normalized);
    }
  }
  return out;
}

std::vector<uint32_t> read_index_accessor(const GltfContext& ctx, int accessor, const std::string& what) {
  const AccessorElements b = view_accessor(ctx, accessor, what);
  const std::string label = what + ": accessor " + std::to_string(accessor);
  if (b.components != 1) {
    ctx.fail(label + " has type " + gltf_type_name(ctx.model.accessors[accessor].type) + "; indices must be SCALAR");
  }
  if (b.normalized) ctx.fail(label + " is normalized; indices must not be");
  const int ct = b.component_type;
  if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    ctx.fail(label + " has component type " + gltf_component_type_name(ct) +
             "; indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  std::vector<uint32_t> out(b.count);
  for (size_t i = 0; i < b.count; ++i) {
    const uint8_t* e = b.element(i);
    if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
      out[i] = e[0];
    } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      out[i] = load<uint16_t>(e);
    } else {
      out[i] = load<uint32_t>(e);
    }
  }
  return out;
}

std::vector<glm::u16vec4> read_joints_accessor(const GltfContext& ctx, int accessor, const std::string& what) {
  const AccessorElements b = view_accessor(ctx, accessor, what);
  const std::string label = what + ": accessor " + std::to_string(accessor);
  const tinygltf::Accessor& a = ctx.model.accessors[accessor];
  if (a.type != TINYGLTF_TYPE_VEC4) ctx.fail(label + " has type " + gltf_type_name(a.type) + "; joints must be VEC4");
  const int ct = b.component_type;
  if ((ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) || b.normalized) {
    ctx.fail(label + " has component type " + gltf_component_type_name(ct) + (b.normalized ? " (normalized)" : "") +
             "; joints must be UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized");
  }
  std::vector<glm::u16vec4> out(b.count);
  for (size_t i = 0; i < b.count; ++i) {
    const uint8_t* e = b.element(i);
    for (int c = 0; c < 4; ++c) {
      out[i][c] = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? e[c] : load<uint16_t>(e + 2 * c);
    }
  }
  return out;
}

}  // namespace cr

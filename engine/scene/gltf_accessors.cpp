#include "engine/scene/gltf_accessors.h"

#include <cstring>

namespace cr {

namespace {

// A validated accessor: element i starts at base + i * stride.
struct AccessorBytes {
  const uint8_t* base = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
  int components = 0;
  bool normalized = false;
};

int component_size(int component_type) {
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

int component_count(int type) {
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

std::string type_name(int type) {
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

std::string component_type_name(int component_type) {
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

AccessorBytes view_accessor(const GltfContext& ctx, int index, const std::string& what) {
  const tinygltf::Model& m = ctx.model;
  if (index < 0 || static_cast<size_t>(index) >= m.accessors.size()) {
    ctx.fail(what + ": accessor index " + std::to_string(index) + " out of range (" +
             std::to_string(m.accessors.size()) + " accessors)");
  }
  const tinygltf::Accessor& a = m.accessors[index];
  std::string label = what + ": accessor " + std::to_string(index);
  if (a.sparse.isSparse) ctx.fail(label + " is sparse; sparse accessors are not supported");
  int csize = component_size(a.componentType);
  int ncomp = component_count(a.type);
  if (csize == 0) ctx.fail(label + " has invalid componentType " + std::to_string(a.componentType));
  if (ncomp == 0) ctx.fail(label + " has invalid type " + std::to_string(a.type));
  if (a.count < 1) ctx.fail(label + " has count 0 (must be at least 1)");
  if (a.count > kMaxAccessorCount) {
    ctx.fail(label + " has count " + std::to_string(a.count) + ", above the limit of " +
             std::to_string(kMaxAccessorCount));
  }
  if (a.bufferView < 0 || static_cast<size_t>(a.bufferView) >= m.bufferViews.size()) {
    ctx.fail(label + " has bufferView " + std::to_string(a.bufferView) + " out of range (" +
             std::to_string(m.bufferViews.size()) + " bufferViews); accessors without data are not supported");
  }
  const tinygltf::BufferView& bv = m.bufferViews[a.bufferView];
  std::string bv_label = "bufferView " + std::to_string(a.bufferView);
  if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= m.buffers.size()) {
    ctx.fail(label + ": " + bv_label + " has buffer " + std::to_string(bv.buffer) + " out of range (" +
             std::to_string(m.buffers.size()) + " buffers)");
  }
  const size_t buffer_size = m.buffers[bv.buffer].data.size();
  if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset) {
    ctx.fail(label + ": " + bv_label + " (byteOffset " + std::to_string(bv.byteOffset) + ", byteLength " +
             std::to_string(bv.byteLength) + ") extends past the end of buffer " + std::to_string(bv.buffer) +
             " (" + std::to_string(buffer_size) + " bytes)");
  }
  const size_t element = static_cast<size_t>(csize) * static_cast<size_t>(ncomp);
  size_t stride = element;
  if (bv.byteStride != 0) {
    if (bv.byteStride < element || bv.byteStride > 252) {
      ctx.fail(label + ": " + bv_label + " byteStride " + std::to_string(bv.byteStride) +
               " must be in [" + std::to_string(element) + ", 252] for " + type_name(a.type) + " " +
               component_type_name(a.componentType));
    }
    stride = bv.byteStride;
  }
  // count <= 2^28 and stride <= 252, so the product cannot overflow 64 bits.
  const uint64_t needed = static_cast<uint64_t>(a.count - 1) * stride + element;
  if (a.byteOffset > bv.byteLength || needed > bv.byteLength - a.byteOffset) {
    ctx.fail(label + " (byteOffset " + std::to_string(a.byteOffset) + ", count " + std::to_string(a.count) +
             ", stride " + std::to_string(stride) + ") needs " + std::to_string(a.byteOffset + needed) +
             " bytes but " + bv_label + " has " + std::to_string(bv.byteLength));
  }
  AccessorBytes out;
  out.base = m.buffers[bv.buffer].data.data() + bv.byteOffset + a.byteOffset;
  out.stride = stride;
  out.count = a.count;
  out.component_type = a.componentType;
  out.components = ncomp;
  out.normalized = a.normalized;
  return out;
}

template <typename T>
T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

}  // namespace

size_t check_accessor(const GltfContext& ctx, int accessor, const std::string& what) {
  return view_accessor(ctx, accessor, what).count;
}

FloatAccessor read_float_accessor(const GltfContext& ctx, int accessor, const std::string& what,
                                  std::initializer_list<int> types, AttributeKind kind) {
  const bool allow_unorm = kind == AttributeKind::Texcoord || kind == AttributeKind::Color;
  AccessorBytes b = view_accessor(ctx, accessor, what);
  const tinygltf::Accessor& a = ctx.model.accessors[accessor];
  bool type_ok = false;
  std::string allowed;
  for (int t : types) {
    type_ok = type_ok || t == a.type;
    allowed += (allowed.empty() ? "" : " or ") + type_name(t);
  }
  std::string label = what + ": accessor " + std::to_string(accessor);
  if (!type_ok) ctx.fail(label + " has type " + type_name(a.type) + "; expected " + allowed);
  const bool is_float = b.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool is_unorm = (b.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         b.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) && b.normalized;
  if (!is_float && !(allow_unorm && is_unorm)) {
    ctx.fail(label + " has component type " + component_type_name(b.component_type) +
             (b.normalized ? " (normalized)" : "") + "; expected FLOAT" +
             (allow_unorm ? " or normalized UNSIGNED_BYTE/UNSIGNED_SHORT" : ""));
  }
  FloatAccessor out;
  out.components = b.components;
  out.count = b.count;
  out.values.resize(b.count * static_cast<size_t>(b.components));
  for (size_t i = 0; i < b.count; ++i) {
    const uint8_t* e = b.base + i * b.stride;
    for (int c = 0; c < b.components; ++c) {
      float v = 0.0f;
      switch (b.component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: v = load<float>(e + 4 * c); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = static_cast<float>(e[c]) / 255.0f; break;
        default: v = static_cast<float>(load<uint16_t>(e + 2 * c)) / 65535.0f; break;
      }
      out.values[i * b.components + c] = v;
    }
  }
  return out;
}

std::vector<uint32_t> read_index_accessor(const GltfContext& ctx, int accessor, const std::string& what) {
  AccessorBytes b = view_accessor(ctx, accessor, what);
  std::string label = what + ": accessor " + std::to_string(accessor);
  if (b.components != 1) ctx.fail(label + " has type " + type_name(ctx.model.accessors[accessor].type) + "; indices must be SCALAR");
  if (b.normalized) ctx.fail(label + " is normalized; indices must not be");
  const int ct = b.component_type;
  if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    ctx.fail(label + " has component type " + component_type_name(ct) +
             "; indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  std::vector<uint32_t> out(b.count);
  for (size_t i = 0; i < b.count; ++i) {
    const uint8_t* e = b.base + i * b.stride;
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

}  // namespace cr

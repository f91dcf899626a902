#include "engine/scene/gltf_draco.h"

#include <cstring>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include <draco/compression/decode.h>

#include "engine/scene/gltf_accessors.h"

namespace cr {

namespace {

constexpr const char* kExtension = "KHR_draco_mesh_compression";

// A primitive's extension object.
struct DracoPrimitive {
  int buffer_view = -1;
  std::map<std::string, int> attributes;  // semantic -> Draco attribute unique id
};

int non_negative_int(const GltfContext& ctx, const std::string& field, const tinygltf::Value& v) {
  if (!v.IsInt() || v.Get<int>() < 0) ctx.fail(field + " must be a non-negative integer");
  return v.Get<int>();
}

DracoPrimitive parse_extension(const GltfContext& ctx, const std::string& label, const tinygltf::Value& ext) {
  const std::string field = label + " " + kExtension;
  DracoPrimitive out;
  out.buffer_view = non_negative_int(ctx, field + ".bufferView", ext.Get("bufferView"));
  const tinygltf::Value& attributes = ext.Get("attributes");
  if (!attributes.IsObject()) ctx.fail(field + ".attributes must be an object");
  for (const std::string& semantic : attributes.Keys()) {
    out.attributes[semantic] = non_negative_int(ctx, field + ".attributes." + semantic, attributes.Get(semantic));
  }
  return out;
}

std::unique_ptr<draco::Mesh> decode_mesh(const GltfContext& ctx, const std::string& label, int view) {
  const std::span<const uint8_t> bytes = gltf_buffer_view_bytes(ctx, label + " " + kExtension, view);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  draco::StatusOr<std::unique_ptr<draco::Mesh>> mesh = decoder.DecodeMeshFromBuffer(&buffer);
  if (!mesh.ok() || !mesh.value()) {
    ctx.fail(label + ": the " + kExtension + " data in bufferView " + std::to_string(view) + " does not decode (" +
             (mesh.ok() ? std::string("no mesh") : mesh.status().error_msg_string()) + ")");
  }
  return std::move(mesh).value();
}

// A copy of accessor `index` as the file declares it (a copy: the model's
// accessors grow while primitives are decoded).
tinygltf::Accessor declared_accessor(const GltfContext& ctx, const tinygltf::Model& model, int index,
                                     const std::string& what) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    ctx.fail(what + ": accessor index " + std::to_string(index) + " out of range (" +
             std::to_string(model.accessors.size()) + " accessors)");
  }
  const tinygltf::Accessor& a = model.accessors[index];
  if (a.count > kMaxAccessorCount) {
    ctx.fail(what + ": accessor " + std::to_string(index) + " has count " + std::to_string(a.count) +
             ", above the limit of " + std::to_string(kMaxAccessorCount));
  }
  return a;
}

// `declared` with its data in a new buffer of the model; returns its index.
int append_accessor(tinygltf::Model& model, tinygltf::Accessor declared, std::vector<unsigned char> bytes) {
  tinygltf::BufferView view;
  view.buffer = static_cast<int>(model.buffers.size());
  view.byteOffset = 0;
  view.byteLength = bytes.size();
  tinygltf::Buffer buffer;
  buffer.data = std::move(bytes);
  model.buffers.push_back(std::move(buffer));
  model.bufferViews.push_back(std::move(view));
  declared.bufferView = static_cast<int>(model.bufferViews.size()) - 1;
  declared.byteOffset = 0;
  declared.sparse.isSparse = false;  // the extension forbids sparse on its accessors; the decoded data is whole
  model.accessors.push_back(std::move(declared));
  return static_cast<int>(model.accessors.size()) - 1;
}

template <typename T>
void store(std::vector<unsigned char>& out, size_t i, T v) {
  std::memcpy(out.data() + i * sizeof(T), &v, sizeof(T));
}

// The triangle list of `mesh` as `declared`'s component type.
std::vector<unsigned char> decoded_indices(const GltfContext& ctx, const std::string& what, const draco::Mesh& mesh,
                                           const tinygltf::Accessor& declared) {
  const int ct = declared.componentType;
  const uint64_t max_index = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 0xFFu
                             : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 0xFFFFu
                                                                            : 0xFFFFFFFFu;
  const uint64_t points = mesh.num_points();
  if (points > max_index + 1) {
    ctx.fail(what + ": the Draco data has " + std::to_string(points) + " vertices, more than " +
             gltf_component_type_name(ct) + " indices reach");
  }
  const size_t csize = static_cast<size_t>(gltf_component_size(ct));
  std::vector<unsigned char> out(static_cast<size_t>(mesh.num_faces()) * 3 * csize);
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = mesh.face(f)[c].value();
      if (v >= points) {
        ctx.fail(what + ": Draco triangle " + std::to_string(f.value()) + " refers to vertex " + std::to_string(v) +
                 " of " + std::to_string(points));
      }
      const size_t i = static_cast<size_t>(f.value()) * 3 + c;
      if (csize == 1) {
        store(out, i, static_cast<uint8_t>(v));
      } else if (csize == 2) {
        store(out, i, static_cast<uint16_t>(v));
      } else {
        store(out, i, v);
      }
    }
  }
  return out;
}

// The glTF component type that holds Draco values of `type` unchanged; 0 for none.
int gltf_component_type_of(draco::DataType type) {
  switch (type) {
    case draco::DT_INT8: return TINYGLTF_COMPONENT_TYPE_BYTE;
    case draco::DT_UINT8: return TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    case draco::DT_INT16: return TINYGLTF_COMPONENT_TYPE_SHORT;
    case draco::DT_UINT16: return TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    case draco::DT_UINT32: return TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    case draco::DT_FLOAT32: return TINYGLTF_COMPONENT_TYPE_FLOAT;
    default: return 0;
  }
}

// The values of `att` for each of `points` vertices, `components` of type T
// each; false where a value is missing or does not convert.
template <typename T>
bool convert_attribute(const draco::PointAttribute& att, uint32_t points, int components,
                       std::vector<unsigned char>& out) {
  if (!att.is_mapping_identity() && att.indices_map_size() < points) return false;
  out.resize(static_cast<size_t>(points) * components * sizeof(T));
  std::vector<T> value(components);
  for (draco::PointIndex p(0); p < points; ++p) {
    const draco::AttributeValueIndex v = att.mapped_index(p);
    if (v.value() >= att.size() || !att.ConvertValue<T>(v, static_cast<int8_t>(components), value.data())) return false;
    std::memcpy(out.data() + static_cast<size_t>(p.value()) * components * sizeof(T), value.data(),
                components * sizeof(T));
  }
  return true;
}

// Draco attribute `id` of `mesh` as `declared`'s component type, after
// checking it matches the accessor's count, component count and type.
std::vector<unsigned char> decoded_attribute(const GltfContext& ctx, const std::string& what, const draco::Mesh& mesh,
                                             int id, const tinygltf::Accessor& declared, int accessor) {
  const draco::PointAttribute* att = mesh.GetAttributeByUniqueId(static_cast<uint32_t>(id));
  if (!att) ctx.fail(what + ": the Draco data has no attribute with id " + std::to_string(id));
  const std::string acc = "accessor " + std::to_string(accessor);
  if (declared.count != mesh.num_points()) {
    ctx.fail(what + ": " + acc + " declares count " + std::to_string(declared.count) + " but the Draco data has " +
             std::to_string(mesh.num_points()) + " vertices");
  }
  const int components = gltf_component_count(declared.type);
  if (components == 0) ctx.fail(what + ": " + acc + " has invalid type " + std::to_string(declared.type));
  if (att->num_components() != components) {
    ctx.fail(what + ": " + acc + " declares " + gltf_type_name(declared.type) + " but Draco attribute " +
             std::to_string(id) + " has " + std::to_string(att->num_components()) + " components");
  }
  const int ct = declared.componentType;
  // Integers are copied unchanged, so the accessor's normalized flag reads
  // them as the file means; FLOAT takes Draco's own conversion.
  const int stored = gltf_component_type_of(att->data_type());
  if (ct != TINYGLTF_COMPONENT_TYPE_FLOAT && stored != ct) {
    ctx.fail(what + ": " + acc + " declares " + gltf_component_type_name(ct) + " but Draco attribute " +
             std::to_string(id) + " stores " +
             (stored ? gltf_component_type_name(stored) : "Draco data type " + std::to_string(att->data_type())));
  }
  std::vector<unsigned char> out;
  const uint32_t points = mesh.num_points();
  bool ok = false;
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: ok = convert_attribute<float>(*att, points, components, out); break;
    case TINYGLTF_COMPONENT_TYPE_BYTE: ok = convert_attribute<int8_t>(*att, points, components, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: ok = convert_attribute<uint8_t>(*att, points, components, out); break;
    case TINYGLTF_COMPONENT_TYPE_SHORT: ok = convert_attribute<int16_t>(*att, points, components, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: ok = convert_attribute<uint16_t>(*att, points, components, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: ok = convert_attribute<uint32_t>(*att, points, components, out); break;
    default: ctx.fail(what + ": " + acc + " has invalid componentType " + std::to_string(ct));
  }
  if (!ok) ctx.fail(what + ": Draco attribute " + std::to_string(id) + " has missing or unconvertible values");
  return out;
}

}  // namespace

void decode_draco_primitives(const GltfContext& ctx, tinygltf::Model& model) {
  // Primitives may share a Draco bufferView: each is decoded once, and each
  // (bufferView, attribute id or -1 for indices, declared accessor) gets one
  // new accessor.
  std::map<int, std::unique_ptr<draco::Mesh>> meshes;
  std::map<std::tuple<int, int, int>, int> decoded;
  constexpr int kIndices = -1;
  for (size_t mi = 0; mi < model.meshes.size(); ++mi) {
    for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      tinygltf::Primitive& p = model.meshes[mi].primitives[pi];
      auto ext = p.extensions.find(kExtension);
      if (ext == p.extensions.end()) continue;
      const std::string label = gltf_label("mesh", mi, model.meshes[mi].name) + " primitive " + std::to_string(pi);
      const int mode = p.mode == -1 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES) {
        ctx.fail(label + " uses " + kExtension + " with mode " + std::to_string(mode) +
                 "; only TRIANGLES (4) is decoded");
      }
      const DracoPrimitive draco = parse_extension(ctx, label, ext->second);
      std::unique_ptr<draco::Mesh>& mesh = meshes[draco.buffer_view];
      if (!mesh) mesh = decode_mesh(ctx, label, draco.buffer_view);

      const std::string indices_what = label + " indices";
      tinygltf::Accessor indices;
      if (p.indices >= 0) {
        indices = declared_accessor(ctx, model, p.indices, indices_what);
      } else {
        indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        indices.type = TINYGLTF_TYPE_SCALAR;
        indices.count = static_cast<size_t>(mesh->num_faces()) * 3;
      }
      const int ict = indices.componentType;
      if (indices.type != TINYGLTF_TYPE_SCALAR ||
          (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
           ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
        ctx.fail(indices_what + ": accessor " + std::to_string(p.indices) + " is " + gltf_type_name(indices.type) +
                 " " + gltf_component_type_name(ict) +
                 "; indices must be SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
      }
      if (indices.count != static_cast<size_t>(mesh->num_faces()) * 3) {
        ctx.fail(indices_what + ": accessor " + std::to_string(p.indices) + " declares count " +
                 std::to_string(indices.count) + " but the Draco data has " + std::to_string(mesh->num_faces()) +
                 " triangles");
      }
      int& new_indices = decoded.try_emplace({draco.buffer_view, kIndices, p.indices}, -1).first->second;
      if (new_indices < 0) {
        new_indices = append_accessor(model, indices, decoded_indices(ctx, indices_what, *mesh, indices));
      }
      p.indices = new_indices;

      for (const auto& [semantic, id] : draco.attributes) {
        const std::string what = label + " attribute " + semantic;
        auto it = p.attributes.find(semantic);
        if (it == p.attributes.end()) {
          ctx.fail(label + ": " + kExtension + " names attribute " + semantic + ", which the primitive does not have");
        }
        int& new_accessor = decoded.try_emplace({draco.buffer_view, id, it->second}, -1).first->second;
        if (new_accessor < 0) {
          const tinygltf::Accessor declared = declared_accessor(ctx, model, it->second, what);
          new_accessor = append_accessor(model, declared, decoded_attribute(ctx, what, *mesh, id, declared, it->second));
        }
        it->second = new_accessor;
      }
      p.extensions.erase(ext);
    }
  }
}

}  // namespace cr

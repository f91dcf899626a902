#include "engine/scene/gltf_schema.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "engine/core/error.h"

namespace cr {

namespace {

enum class Kind {
  Uint, Number, Bool, String, Object, ArrayOfUint, ArrayOfNumber, ArrayOfString, ArrayOfObject, MapOfUint,
  ArrayOfMapOfUint
};

// One property: its name, JSON kind, for objects the schema of the value, and
// for fixed-size arrays their size (tinygltf drops a baseColorFactor of 3).
struct Property {
  const char* name;
  Kind kind;
  const char* schema = nullptr;
  bool required = false;
  size_t size = 0;
};

// The core glTF 2.0 schema, reduced to what decides how a file is read.
const std::map<std::string, std::vector<Property>>& schemas() {
  static const std::map<std::string, std::vector<Property>> s = {
      {"glTF",
       {{"asset", Kind::Object, "asset", true}, {"scene", Kind::Uint}, {"scenes", Kind::ArrayOfObject, "scene"},
        {"nodes", Kind::ArrayOfObject, "node"}, {"meshes", Kind::ArrayOfObject, "mesh"},
        {"accessors", Kind::ArrayOfObject, "accessor"}, {"bufferViews", Kind::ArrayOfObject, "bufferView"},
        {"buffers", Kind::ArrayOfObject, "buffer"}, {"materials", Kind::ArrayOfObject, "material"},
        {"textures", Kind::ArrayOfObject, "texture"}, {"images", Kind::ArrayOfObject, "image"},
        {"samplers", Kind::ArrayOfObject, "sampler"}, {"cameras", Kind::ArrayOfObject, "camera"},
        {"skins", Kind::ArrayOfObject, "skin"}, {"animations", Kind::ArrayOfObject, "animation"},
        {"extensionsUsed", Kind::ArrayOfString}, {"extensionsRequired", Kind::ArrayOfString}}},
      {"asset", {{"version", Kind::String, nullptr, true}, {"minVersion", Kind::String}, {"generator", Kind::String}, {"copyright", Kind::String}}},
      {"scene", {{"name", Kind::String}, {"nodes", Kind::ArrayOfUint}}},
      {"node",
       {{"name", Kind::String}, {"children", Kind::ArrayOfUint}, {"mesh", Kind::Uint}, {"camera", Kind::Uint},
        {"skin", Kind::Uint}, {"matrix", Kind::ArrayOfNumber, nullptr, false, 16},
        {"rotation", Kind::ArrayOfNumber, nullptr, false, 4}, {"scale", Kind::ArrayOfNumber, nullptr, false, 3},
        {"translation", Kind::ArrayOfNumber, nullptr, false, 3}, {"weights", Kind::ArrayOfNumber}}},
      {"mesh",
       {{"name", Kind::String}, {"primitives", Kind::ArrayOfObject, "primitive", true}, {"weights", Kind::ArrayOfNumber}}},
      {"primitive",
       {{"attributes", Kind::MapOfUint, nullptr, true}, {"indices", Kind::Uint}, {"material", Kind::Uint},
        {"mode", Kind::Uint}, {"targets", Kind::ArrayOfMapOfUint}}},
      {"accessor",
       {{"name", Kind::String}, {"bufferView", Kind::Uint}, {"byteOffset", Kind::Uint},
        {"componentType", Kind::Uint, nullptr, true}, {"normalized", Kind::Bool}, {"count", Kind::Uint, nullptr, true},
        {"type", Kind::String, nullptr, true}, {"max", Kind::ArrayOfNumber}, {"min", Kind::ArrayOfNumber},
        {"sparse", Kind::Object, "accessorSparse"}}},
      {"accessorSparse",
       {{"count", Kind::Uint, nullptr, true}, {"indices", Kind::Object, "accessorSparseIndices", true},
        {"values", Kind::Object, "accessorSparseValues", true}}},
      {"accessorSparseIndices",
       {{"bufferView", Kind::Uint, nullptr, true}, {"byteOffset", Kind::Uint}, {"componentType", Kind::Uint, nullptr, true}}},
      {"accessorSparseValues", {{"bufferView", Kind::Uint, nullptr, true}, {"byteOffset", Kind::Uint}}},
      {"bufferView",
       {{"name", Kind::String}, {"buffer", Kind::Uint, nullptr, true}, {"byteOffset", Kind::Uint},
        {"byteLength", Kind::Uint, nullptr, true}, {"byteStride", Kind::Uint}, {"target", Kind::Uint}}},
      {"buffer", {{"name", Kind::String}, {"uri", Kind::String}, {"byteLength", Kind::Uint, nullptr, true}}},
      {"material",
       {{"name", Kind::String}, {"pbrMetallicRoughness", Kind::Object, "pbrMetallicRoughness"},
        {"normalTexture", Kind::Object, "textureInfo"}, {"occlusionTexture", Kind::Object, "textureInfo"},
        {"emissiveTexture", Kind::Object, "textureInfo"}, {"emissiveFactor", Kind::ArrayOfNumber, nullptr, false, 3},
        {"alphaMode", Kind::String}, {"alphaCutoff", Kind::Number}, {"doubleSided", Kind::Bool}}},
      {"pbrMetallicRoughness",
       {{"baseColorFactor", Kind::ArrayOfNumber, nullptr, false, 4}, {"baseColorTexture", Kind::Object, "textureInfo"},
        {"metallicFactor", Kind::Number}, {"roughnessFactor", Kind::Number},
        {"metallicRoughnessTexture", Kind::Object, "textureInfo"}}},
      {"textureInfo",
       {{"index", Kind::Uint, nullptr, true}, {"texCoord", Kind::Uint}, {"scale", Kind::Number}, {"strength", Kind::Number}}},
      {"texture", {{"name", Kind::String}, {"sampler", Kind::Uint}, {"source", Kind::Uint}}},
      {"image", {{"name", Kind::String}, {"uri", Kind::String}, {"mimeType", Kind::String}, {"bufferView", Kind::Uint}}},
      {"sampler",
       {{"name", Kind::String}, {"magFilter", Kind::Uint}, {"minFilter", Kind::Uint}, {"wrapS", Kind::Uint}, {"wrapT", Kind::Uint}}},
      {"camera",
       {{"name", Kind::String}, {"type", Kind::String, nullptr, true}, {"perspective", Kind::Object, "perspective"},
        {"orthographic", Kind::Object, "orthographic"}}},
      {"orthographic",
       {{"xmag", Kind::Number, nullptr, true}, {"ymag", Kind::Number, nullptr, true},
        {"zfar", Kind::Number, nullptr, true}, {"znear", Kind::Number, nullptr, true}}},
      {"skin",
       {{"name", Kind::String}, {"inverseBindMatrices", Kind::Uint}, {"skeleton", Kind::Uint},
        {"joints", Kind::ArrayOfUint, nullptr, true}}},
      {"animation",
       {{"name", Kind::String}, {"channels", Kind::ArrayOfObject, "animationChannel", true},
        {"samplers", Kind::ArrayOfObject, "animationSampler", true}}},
      {"animationChannel",
       {{"sampler", Kind::Uint, nullptr, true}, {"target", Kind::Object, "animationChannelTarget", true}}},
      {"animationChannelTarget", {{"node", Kind::Uint}, {"path", Kind::String, nullptr, true}}},
      {"animationSampler",
       {{"input", Kind::Uint, nullptr, true}, {"interpolation", Kind::String}, {"output", Kind::Uint, nullptr, true}}},
      {"perspective",
       {{"aspectRatio", Kind::Number}, {"yfov", Kind::Number, nullptr, true}, {"zfar", Kind::Number},
        {"znear", Kind::Number, nullptr, true}}},
  };
  return s;
}

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Uint: return "a non-negative integer";
    case Kind::Number: return "a number";
    case Kind::Bool: return "a boolean";
    case Kind::String: return "a string";
    case Kind::Object: return "an object";
    case Kind::ArrayOfUint: return "an array of non-negative integers";
    case Kind::ArrayOfNumber: return "an array of numbers";
    case Kind::ArrayOfString: return "an array of strings";
    case Kind::ArrayOfObject: return "an array of objects";
    case Kind::MapOfUint: return "an object of non-negative integers";
    case Kind::ArrayOfMapOfUint: return "an array of objects of non-negative integers";
  }
  return "";
}

const char* element_name(Kind array_kind) {
  switch (array_kind) {
    case Kind::ArrayOfUint: return "a non-negative integer";
    case Kind::ArrayOfNumber: return "a number";
    case Kind::ArrayOfString: return "a string";
    default: return "an object";
  }
}

bool is_uint(const nlohmann::json& v) {
  if (v.is_number_unsigned()) return v.get<uint64_t>() <= uint64_t(INT32_MAX);
  if (v.is_number_integer()) return v.get<int64_t>() >= 0 && v.get<int64_t>() <= INT32_MAX;
  return false;
}

class SchemaChecker {
 public:
  explicit SchemaChecker(const std::string& path) : path_(path) {}

  void object(const nlohmann::json& v, const std::string& schema, const std::string& where) {
    const std::vector<Property>& props = schemas().at(schema);
    for (const Property& p : props) {
      auto it = v.find(p.name);
      std::string field = where.empty() ? p.name : where + "." + p.name;
      if (it == v.end()) {
        if (p.required) fail(field, "is required");
        continue;
      }
      value(*it, p, field);
    }
    if (auto ext = v.find("extensions"); ext != v.end()) {
      std::string field = where.empty() ? "extensions" : where + ".extensions";
      if (!ext->is_object()) fail(field, "must be an object, found " + std::string(ext->type_name()));
      for (auto e = ext->begin(); e != ext->end(); ++e) {
        if (!e->is_object()) fail(field + "." + e.key(), "must be an object, found " + std::string(e->type_name()));
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(path_, "invalid glTF: '" + field + "' " + what);
  }

  void expect(bool ok, const nlohmann::json& v, const Property& p, const std::string& field) const {
    if (!ok) fail(field, "must be " + std::string(kind_name(p.kind)) + ", found " + v.dump().substr(0, 60));
  }

  void value(const nlohmann::json& v, const Property& p, const std::string& field) {
    switch (p.kind) {
      case Kind::Uint: expect(is_uint(v), v, p, field); break;
      case Kind::Number: expect(v.is_number(), v, p, field); break;
      case Kind::Bool: expect(v.is_boolean(), v, p, field); break;
      case Kind::String: expect(v.is_string(), v, p, field); break;
      case Kind::Object:
        expect(v.is_object(), v, p, field);
        object(v, p.schema, field);
        break;
      case Kind::ArrayOfUint:
      case Kind::ArrayOfNumber:
      case Kind::ArrayOfString:
      case Kind::ArrayOfObject:
      case Kind::ArrayOfMapOfUint: {
        expect(v.is_array(), v, p, field);
        for (size_t i = 0; i < v.size(); ++i) {
          const nlohmann::json& e = v[i];
          bool ok = p.kind == Kind::ArrayOfUint     ? is_uint(e)
                    : p.kind == Kind::ArrayOfNumber ? e.is_number()
                    : p.kind == Kind::ArrayOfString ? e.is_string()
                                                    : e.is_object();
          std::string item = field + "[" + std::to_string(i) + "]";
          if (!ok) fail(item, "must be " + std::string(element_name(p.kind)) + ", found " + e.dump().substr(0, 60));
          if (p.kind == Kind::ArrayOfObject) object(e, p.schema, item);
          if (p.kind == Kind::ArrayOfMapOfUint) uints(e, item);
        }
        if (p.size != 0 && v.size() != p.size) {
          fail(field, "must be an array of " + std::to_string(p.size) + " numbers, found " + v.dump().substr(0, 60));
        }
        break;
      }
      case Kind::MapOfUint:
        expect(v.is_object(), v, p, field);
        uints(v, field);
        break;
    }
  }

  // tinygltf drops a member that is not an integer (a morph target's
  // "POSITION": 0.5), so the file would lose it silently.
  void uints(const nlohmann::json& map, const std::string& field) const {
    for (auto e = map.begin(); e != map.end(); ++e) {
      if (!is_uint(*e)) fail(field + "." + e.key(), "must be a non-negative integer, found " + e->dump().substr(0, 60));
    }
  }

  const std::string& path_;
};

// tinygltf hands image bytes from a bufferView to the image callback without
// checking that the view lies inside its buffer; check it here, on the
// declared sizes (tinygltf checks each buffer's data against its byteLength).
void check_buffer_views(const std::string& path, const nlohmann::json& doc) {
  static const nlohmann::json kEmpty = nlohmann::json::array();
  const nlohmann::json& buffers = doc.contains("buffers") ? doc["buffers"] : kEmpty;
  const nlohmann::json& views = doc.contains("bufferViews") ? doc["bufferViews"] : kEmpty;
  for (size_t i = 0; i < views.size(); ++i) {
    const nlohmann::json& v = views[i];
    std::string label = "invalid glTF: bufferViews[" + std::to_string(i) + "]";
    uint64_t b = v["buffer"].get<uint64_t>();
    if (b >= buffers.size()) {
      throw InputError(path, label + " buffer " + std::to_string(b) + " out of range (" + std::to_string(buffers.size()) + " buffers)");
    }
    uint64_t offset = v.value("byteOffset", uint64_t(0));
    uint64_t length = v["byteLength"].get<uint64_t>();
    uint64_t buffer_length = buffers[b]["byteLength"].get<uint64_t>();
    if (length == 0 || offset + length > buffer_length) {
      throw InputError(path, label + " (byteOffset " + std::to_string(offset) + ", byteLength " + std::to_string(length) +
                                 ") does not fit in buffer " + std::to_string(b) + " (" + std::to_string(buffer_length) + " bytes)");
    }
  }
}

// A node's transform is a matrix or TRS, never both: tinygltf reads the
// matrix and drops the TRS, so the loader could not see the conflict.
void check_node_transforms(const std::string& path, const nlohmann::json& doc) {
  auto nodes = doc.find("nodes");
  if (nodes == doc.end()) return;
  for (size_t i = 0; i < nodes->size(); ++i) {
    const nlohmann::json& n = (*nodes)[i];
    if (!n.contains("matrix")) continue;
    for (const char* trs : {"translation", "rotation", "scale"}) {
      if (n.contains(trs)) {
        throw InputError(path, "invalid glTF: 'nodes[" + std::to_string(i) + "]' has both 'matrix' and '" + trs +
                                   "'; a node's transform is either a matrix or translation/rotation/scale");
      }
    }
  }
}

bool is_base64(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/';
}

// The data URIs of doc[array] must be base64 of one of `types`, with nothing
// after the data. tinygltf decodes any type it knows anywhere (a buffer of
// image/png), takes other types for file names, and stops decoding at the
// first character that is not base64, dropping the rest unseen.
void check_data_uris(const std::string& path, const nlohmann::json& doc, const char* array,
                     const std::vector<std::string>& types, const char* whose) {
  auto items = doc.find(array);
  if (items == doc.end()) return;
  for (size_t i = 0; i < items->size(); ++i) {
    auto it = (*items)[i].find("uri");
    if (it == (*items)[i].end() || it->get<std::string>().rfind("data:", 0) != 0) continue;
    const std::string& uri = it->get_ref<const std::string&>();
    const std::string field = std::string(array) + "[" + std::to_string(i) + "].uri";
    const auto fail = [&](const std::string& what) { throw InputError(path, "invalid glTF: '" + field + "' " + what); };
    const size_t comma = uri.find(',');
    const std::string base64 = ";base64";
    if (comma == std::string::npos || comma < 5 + base64.size() || uri.compare(comma - base64.size(), base64.size(), base64) != 0) {
      fail("is a data URI without \";base64,\"; glTF data URIs must be base64");
    }
    const std::string type = uri.substr(5, comma - base64.size() - 5);
    if (std::find(types.begin(), types.end(), type) == types.end()) {
      std::string allowed;
      for (const std::string& t : types) allowed += (allowed.empty() ? "" : " or ") + t;
      fail("is a data URI of type " + type + "; " + whose + " must be " + allowed);
    }
    size_t end = comma + 1;
    while (end < uri.size() && is_base64(uri[end])) ++end;
    for (int pad = 0; pad < 2 && end < uri.size() && uri[end] == '='; ++pad) ++end;
    if (end == uri.size()) continue;
    const size_t extra = uri.size() - end;
    const std::string shown = extra > 20 ? uri.substr(end, 20) + "..." : uri.substr(end);
    fail("has " + std::to_string(extra) + " characters after its base64 data: " +
         nlohmann::json(shown).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  }
}

}  // namespace

bool gltf_extension_supported(const std::string& name) {
  // One line per extension (docs/scene.md: "Supported").
  static const std::set<std::string> supported = {
      "KHR_lights_punctual",
      "EXT_mesh_gpu_instancing",
      "KHR_mesh_quantization",
      "KHR_draco_mesh_compression",
      "EXT_meshopt_compression",
      "KHR_texture_transform",
      "KHR_materials_emissive_strength",
      "KHR_materials_unlit",
  };
  return supported.count(name) > 0;
}

void validate_gltf_schema(const std::string& path, const nlohmann::json& doc) {
  if (!doc.is_object()) throw InputError(path, "invalid glTF: the document must be a JSON object");
  SchemaChecker(path).object(doc, "glTF", "");
  check_buffer_views(path, doc);
  check_node_transforms(path, doc);
  check_data_uris(path, doc, "buffers", {"application/octet-stream", "application/gltf-buffer"}, "a buffer's");
  check_data_uris(path, doc, "images", {"image/png", "image/jpeg"}, "an image's");
  if (auto req = doc.find("extensionsRequired"); req != doc.end()) {
    for (const nlohmann::json& e : *req) {
      std::string name = e.get<std::string>();
      if (!gltf_extension_supported(name)) {
        throw InputError(path, "requires extension " + name + ", which this renderer does not support");
      }
    }
  }
}

}  // namespace cr

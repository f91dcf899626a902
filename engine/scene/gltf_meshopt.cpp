#include "engine/scene/gltf_meshopt.h"

#include <set>

#include <meshoptimizer.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_accessors.h"

namespace cr {

namespace {

constexpr const char* kMeshoptExtension = "EXT_meshopt_compression";

// What tinygltf reads for a fallback buffer: one zero byte (it rejects empty
// data URIs). Nothing reads it: every view of the buffer is repointed.
constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AA==";

const nlohmann::json* extension_of(const nlohmann::json& object) {
  auto ext = object.find("extensions");
  if (ext == object.end()) return nullptr;
  auto it = ext->find(kMeshoptExtension);
  return it == ext->end() ? nullptr : &*it;
}

const char* mode_name(MeshoptMode m) {
  switch (m) {
    case MeshoptMode::Attributes: return "ATTRIBUTES";
    case MeshoptMode::Triangles: return "TRIANGLES";
    case MeshoptMode::Indices: return "INDICES";
  }
  return "";
}

const char* filter_name(MeshoptFilter f) {
  switch (f) {
    case MeshoptFilter::None: return "NONE";
    case MeshoptFilter::Octahedral: return "OCTAHEDRAL";
    case MeshoptFilter::Quaternion: return "QUATERNION";
    case MeshoptFilter::Exponential: return "EXPONENTIAL";
  }
  return "";
}

// Reads one bufferView's extension object and checks the extension's rules.
class ViewParser {
 public:
  ViewParser(const std::string& path, size_t index) : path_(path), label_("bufferViews[" + std::to_string(index) + "]") {}

  MeshoptView parse(const nlohmann::json& view, const nlohmann::json& ext, int index) {
    MeshoptView v;
    v.buffer_view = index;
    v.buffer = static_cast<int>(uint_field(ext, "buffer", true));
    v.byte_offset = uint_field(ext, "byteOffset", false);
    v.byte_length = uint_field(ext, "byteLength", true);
    v.byte_stride = uint_field(ext, "byteStride", true);
    v.count = uint_field(ext, "count", true);
    const std::string mode = string_field(ext, "mode", "");
    if (mode == "ATTRIBUTES") {
      v.mode = MeshoptMode::Attributes;
    } else if (mode == "TRIANGLES") {
      v.mode = MeshoptMode::Triangles;
    } else if (mode == "INDICES") {
      v.mode = MeshoptMode::Indices;
    } else {
      fail("mode \"" + mode + "\" must be ATTRIBUTES, TRIANGLES or INDICES");
    }
    const std::string filter = string_field(ext, "filter", "NONE");
    if (filter == "NONE") {
      v.filter = MeshoptFilter::None;
    } else if (filter == "OCTAHEDRAL") {
      v.filter = MeshoptFilter::Octahedral;
    } else if (filter == "QUATERNION") {
      v.filter = MeshoptFilter::Quaternion;
    } else if (filter == "EXPONENTIAL") {
      v.filter = MeshoptFilter::Exponential;
    } else {
      fail("filter \"" + filter + "\" must be NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
    check_layout(v, view.value("byteStride", uint64_t(0)), view["byteLength"].get<uint64_t>());
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, label_ + " " + kMeshoptExtension + ": " + what);
  }

  uint64_t uint_field(const nlohmann::json& ext, const char* name, bool required) const {
    auto it = ext.find(name);
    if (it == ext.end()) {
      if (required) fail(std::string(name) + " is required");
      return 0;
    }
    // The bound keeps every value exact through tinygltf's int fields.
    const bool ok = (it->is_number_unsigned() || (it->is_number_integer() && it->get<int64_t>() >= 0)) &&
                    it->get<uint64_t>() <= uint64_t(INT32_MAX);
    if (!ok) fail(std::string(name) + " must be a non-negative integer, found " + it->dump().substr(0, 40));
    return it->get<uint64_t>();
  }

  std::string string_field(const nlohmann::json& ext, const char* name, const char* fallback) const {
    auto it = ext.find(name);
    if (it == ext.end()) {
      if (!*fallback) fail(std::string(name) + " is required");
      return fallback;
    }
    if (!it->is_string()) fail(std::string(name) + " must be a string, found " + it->dump().substr(0, 40));
    return it->get<std::string>();
  }

  // The extension's rules on the layout: what the decoder and the filters
  // accept, and a decoded size equal to the parent view's.
  void check_layout(const MeshoptView& v, uint64_t parent_stride, uint64_t parent_length) const {
    const std::string stride = "byteStride " + std::to_string(v.byte_stride);
    if (parent_stride != 0 && parent_stride != v.byte_stride) {
      fail(stride + " differs from the bufferView's byteStride " + std::to_string(parent_stride));
    }
    if (v.mode == MeshoptMode::Attributes) {
      if (v.byte_stride == 0 || v.byte_stride % 4 != 0 || v.byte_stride > 256) {
        fail(stride + " must be a multiple of 4 in [4, 256] for mode ATTRIBUTES");
      }
    } else {
      if (v.byte_stride != 2 && v.byte_stride != 4) fail(stride + " must be 2 or 4 for mode " + mode_name(v.mode));
      if (v.filter != MeshoptFilter::None) fail(std::string("filter ") + filter_name(v.filter) + " needs mode ATTRIBUTES");
      if (v.mode == MeshoptMode::Triangles && v.count % 3 != 0) {
        fail("count " + std::to_string(v.count) + " must be a multiple of 3 for mode TRIANGLES");
      }
    }
    if (v.filter == MeshoptFilter::Octahedral && v.byte_stride != 4 && v.byte_stride != 8) {
      fail(stride + " must be 4 or 8 for filter OCTAHEDRAL");
    }
    if (v.filter == MeshoptFilter::Quaternion && v.byte_stride != 8) fail(stride + " must be 8 for filter QUATERNION");
    // Both are below 2^31, so the product is exact.
    if (v.count * v.byte_stride != parent_length) {
      fail("count " + std::to_string(v.count) + " times " + stride + " is " + std::to_string(v.count * v.byte_stride) +
           " bytes but the bufferView's byteLength is " + std::to_string(parent_length));
    }
  }

  const std::string& path_;
  std::string label_;
};

}  // namespace

MeshoptDocument prepare_meshopt_compression(const std::string& path, nlohmann::json& doc) {
  static const nlohmann::json kNone = nlohmann::json::array();
  MeshoptDocument out;
  const nlohmann::json& views = doc.contains("bufferViews") ? doc["bufferViews"] : kNone;
  for (size_t i = 0; i < views.size(); ++i) {
    if (const nlohmann::json* ext = extension_of(views[i])) {
      out.views.push_back(ViewParser(path, i).parse(views[i], *ext, static_cast<int>(i)));
    }
  }
  if (!doc.contains("buffers")) return out;
  nlohmann::json& buffers = doc["buffers"];
  std::set<uint64_t> fallback;
  for (size_t b = 0; b < buffers.size(); ++b) {
    const nlohmann::json* ext = extension_of(buffers[b]);
    if (!ext || !ext->contains("fallback")) continue;
    const nlohmann::json& flag = (*ext)["fallback"];
    if (!flag.is_boolean()) {
      throw InputError(path, "buffers[" + std::to_string(b) + "] " + kMeshoptExtension + ": fallback must be a boolean, found " +
                                 flag.dump().substr(0, 40));
    }
    if (flag.get<bool>()) fallback.insert(b);
  }
  if (fallback.empty()) return out;
  // The extension allows references to a fallback buffer from compressed
  // bufferViews only.
  for (size_t i = 0; i < views.size(); ++i) {
    const uint64_t b = views[i]["buffer"].get<uint64_t>();
    if (fallback.count(b) && !extension_of(views[i])) {
      throw InputError(path, "bufferViews[" + std::to_string(i) + "] reads buffer " + std::to_string(b) + ", an " +
                                 kMeshoptExtension + " fallback buffer, but is not compressed (a fallback buffer holds no data)");
    }
  }
  for (const MeshoptView& v : out.views) {
    if (fallback.count(static_cast<uint64_t>(v.buffer))) {
      throw InputError(path, "bufferViews[" + std::to_string(v.buffer_view) + "] " + kMeshoptExtension + ": buffer " +
                                 std::to_string(v.buffer) + " is a fallback buffer, which holds no compressed data");
    }
  }
  // tinygltf hands images their bufferView's bytes while parsing, before any
  // decoding: those of a fallback buffer would be the placeholder.
  const nlohmann::json& images = doc.contains("images") ? doc["images"] : kNone;
  for (size_t i = 0; i < images.size(); ++i) {
    auto bv = images[i].find("bufferView");
    if (bv == images[i].end() || bv->get<uint64_t>() >= views.size()) continue;
    const uint64_t b = views[bv->get<uint64_t>()]["buffer"].get<uint64_t>();
    if (fallback.count(b)) {
      throw InputError(path, "images[" + std::to_string(i) + "] reads bufferView " + bv->dump() + " of " + kMeshoptExtension +
                                 " fallback buffer " + std::to_string(b) + "; compressed images are not supported");
    }
  }
  for (uint64_t b : fallback) {
    buffers[b]["uri"] = kPlaceholderUri;
    buffers[b]["byteLength"] = 1;
  }
  out.fallback_replaced = true;
  return out;
}

void decode_meshopt_buffer_views(const GltfContext& ctx, tinygltf::Model& model, const std::vector<MeshoptView>& views) {
  for (const MeshoptView& v : views) {
    const std::string label = "bufferView " + std::to_string(v.buffer_view) + " " + kMeshoptExtension;
    if (static_cast<size_t>(v.buffer_view) >= model.bufferViews.size()) {
      ctx.fail(label + ": bufferView out of range (" + std::to_string(model.bufferViews.size()) + " bufferViews)");
    }
    const std::span<const uint8_t> src = gltf_buffer_bytes(ctx, label, v.buffer, v.byte_offset, v.byte_length);
    const size_t count = static_cast<size_t>(v.count);
    const size_t stride = static_cast<size_t>(v.byte_stride);
    std::vector<unsigned char> out(count * stride);
    int rc = 0;
    switch (v.mode) {
      case MeshoptMode::Attributes: rc = meshopt_decodeVertexBuffer(out.data(), count, stride, src.data(), src.size()); break;
      case MeshoptMode::Triangles: rc = meshopt_decodeIndexBuffer(out.data(), count, stride, src.data(), src.size()); break;
      case MeshoptMode::Indices: rc = meshopt_decodeIndexSequence(out.data(), count, stride, src.data(), src.size()); break;
    }
    if (rc != 0) {
      ctx.fail(label + ": the " + std::to_string(src.size()) + "-byte " + mode_name(v.mode) +
               " stream does not decode to " + std::to_string(count) + " elements of " + std::to_string(stride) +
               " bytes (meshopt error " + std::to_string(rc) + ": truncated or corrupt)");
    }
    switch (v.filter) {
      case MeshoptFilter::None: break;
      case MeshoptFilter::Octahedral: meshopt_decodeFilterOct(out.data(), count, stride); break;
      case MeshoptFilter::Quaternion: meshopt_decodeFilterQuat(out.data(), count, stride); break;
      case MeshoptFilter::Exponential: meshopt_decodeFilterExp(out.data(), count, stride); break;
    }
    tinygltf::Buffer decoded;
    decoded.data = std::move(out);
    model.buffers.push_back(std::move(decoded));
    tinygltf::BufferView& view = model.bufferViews[v.buffer_view];
    view.buffer = static_cast<int>(model.buffers.size()) - 1;
    view.byteOffset = 0;
    view.extensions.erase(kMeshoptExtension);
  }
}

}  // namespace cr

#include "engine/scene/gltf_loader.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "engine/scene/gltf_context.h"
#include "engine/scene/gltf_image_decoding.h"
#include "engine/scene/gltf_materials.h"
#include "engine/scene/gltf_meshes.h"
#include "engine/scene/gltf_scene_graph.h"
#include "engine/scene/gltf_schema.h"

namespace cr {

namespace {

namespace fs = std::filesystem;

// tinygltf takes sizes as unsigned int; stay well inside that.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(2) << 30;

bool read_whole_file(const std::string& path, std::vector<unsigned char>& out, std::string& err) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    err = "file not found: " + path;
    return false;
  }
  std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    err = "cannot read " + path + ": " + ec.message();
    return false;
  }
  if (size > kMaxFileBytes) {
    err = path + " is " + std::to_string(size) + " bytes, above the limit of " + std::to_string(kMaxFileBytes);
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out.resize(static_cast<size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(size))) {
    err = "cannot read " + path;
    return false;
  }
  return true;
}

// Filesystem callbacks for tinygltf: no shell-style path expansion (its
// default runs wordexp on URIs from the file) and a size limit on reads.
bool fs_file_exists(const std::string& path, void*) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}
std::string fs_expand_path(const std::string& path, void*) { return path; }
bool fs_read_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::string why;
  if (read_whole_file(path, *out, why)) return true;
  if (err) *err += why + "\n";
  return false;
}
bool fs_write_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

uint32_t read_le32(const unsigned char* p) {
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

// The GLB container checked before tinygltf sees it, so truncated files get a
// precise message and no chunk can reach past the end of the data.
void validate_glb_layout(const std::string& path, const std::vector<unsigned char>& b) {
  const size_t size = b.size();
  if (size < 20) throw InputError(path, "GLB file is truncated: " + std::to_string(size) + " bytes, less than its 20-byte header");
  uint32_t version = read_le32(&b[4]);
  uint32_t length = read_le32(&b[8]);
  if (version != 2) throw InputError(path, "GLB version " + std::to_string(version) + " is not supported (only 2)");
  if (length != size) {
    throw InputError(path, std::string(length > size ? "GLB file is truncated: " : "GLB length mismatch: ") +
                               "header declares " + std::to_string(length) + " bytes, the file has " + std::to_string(size));
  }
  uint64_t json_length = read_le32(&b[12]);
  if (read_le32(&b[16]) != 0x4E4F534Au) throw InputError(path, "GLB first chunk is not JSON");
  uint64_t pos = 20 + json_length;
  if (json_length == 0 || pos > size) {
    throw InputError(path, "GLB JSON chunk of " + std::to_string(json_length) + " bytes does not fit in the file (truncated?)");
  }
  if (pos == size) return;  // no BIN chunk
  if (pos + 8 > size) throw InputError(path, "GLB file is truncated inside the BIN chunk header");
  uint64_t bin_length = read_le32(&b[pos]);
  if (pos + 8 + bin_length > size) {
    throw InputError(path, "GLB BIN chunk of " + std::to_string(bin_length) + " bytes extends past the end of the file (truncated?)");
  }
}

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\n') s.replace(i, 1, "; ");
  }
  return s;
}

// The JSON document (a .gltf file, or a GLB's JSON chunk) parsed on its own,
// so syntax errors carry the parser's position and types can be checked.
nlohmann::json parse_gltf_json(const std::string& path, const unsigned char* begin, const unsigned char* end) {
  try {
    return nlohmann::json::parse(begin, end);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path, std::string("malformed glTF JSON: ") + e.what());
  }
}

void warn_unsupported_extensions(const GltfContext& ctx) {
  for (const std::string& e : ctx.model.extensionsUsed) {
    if (!gltf_extension_supported(e)) ctx.warn("extension " + e + " is not supported and is ignored");
  }
}

}  // namespace

Scene load_gltf(const std::string& path, const GltfLoadOptions& options) {
  std::vector<unsigned char> bytes;
  std::string read_error;
  if (!read_whole_file(path, bytes, read_error)) throw InputError(path, read_error);

  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fs_file_exists, &fs_expand_path, &fs_read_file, &fs_write_file, nullptr});
  ImageDecodeLog decode_log;
  loader.SetImageLoader(&capture_gltf_image, &decode_log);

  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = fs::path(path).parent_path().string();
  const unsigned int size = static_cast<unsigned int>(bytes.size());
  bool ok = false;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    validate_glb_layout(path, bytes);
    const unsigned char* json = bytes.data() + 20;
    validate_gltf_schema(path, parse_gltf_json(path, json, json + read_le32(&bytes[12])));
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, base_dir);
  } else {
    validate_gltf_schema(path, parse_gltf_json(path, bytes.data(), bytes.data() + bytes.size()));
    ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()), size, base_dir);
  }
  if (!ok) throw InputError(path, "invalid glTF: " + one_line(err.empty() ? warn : err));
  if (model.asset.version.rfind("2.", 0) != 0) {
    throw InputError(path, "asset.version is \"" + model.asset.version + "\"; only glTF 2.x is supported");
  }

  GltfContext ctx{model, path};
  warn_unsupported_extensions(ctx);
  Scene scene;
  scene.source = path;
  GltfMaterials materials = load_materials(ctx, decode_log, options);
  GltfMeshes meshes = load_meshes(ctx, materials.materials);
  scene.samplers = std::move(materials.samplers);
  scene.materials = std::move(materials.materials);
  scene.images = std::move(materials.images);
  scene.meshes = std::move(meshes.meshes);
  place_nodes(ctx, meshes, scene);
  return scene;
}

}  // namespace cr

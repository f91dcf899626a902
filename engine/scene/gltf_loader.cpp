#include "engine/scene/gltf_loader.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/json_builder.h"
#include "engine/core/json_input.h"
#include "engine/scene/gltf_context.h"
#include "engine/scene/gltf_draco.h"
#include "engine/scene/gltf_image_decoding.h"
#include "engine/scene/gltf_materials.h"
#include "engine/scene/gltf_meshes.h"
#include "engine/scene/gltf_meshopt.h"
#include "engine/scene/gltf_scene_graph.h"
#include "engine/scene/gltf_schema.h"

namespace cr {

namespace {

namespace fs = std::filesystem;

// tinygltf takes sizes as unsigned int; stay well inside that.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(2) << 30;
// The JSON of a model (a .gltf file, or a GLB's JSON chunk), as the scene and
// profile loaders cap theirs: geometry and images belong in buffers.
constexpr size_t kMaxJsonBytes = size_t(64) << 20;
// Memory one parsed JSON value costs during a load: its node in the
// loader's document, in tinygltf's, and tinygltf's Value copy of extras and
// extensions (8.4 million zeros in extras peaked at 1.8 GB).
constexpr size_t kBytesPerJsonValue = 256;
// How often the parse compares the values read so far with the budget.
constexpr size_t kJsonValuesPerCheck = size_t(1) << 16;
// Values a model's JSON may hold: 4 million is a scene of 300,000 nodes with
// room to spare, and keeps a load within seconds (tinygltf converts every
// value again; 30 million zeros in extras took 6 GB and 44 s).
constexpr size_t kMaxJsonValues = size_t(1) << 22;

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

// Which files a model's URIs may name: those inside its folder (and its
// subfolders) once "..", symlinks and escapes are resolved, unless the user
// allows more. The first path refused is kept for the error message.
struct FileAccess {
  fs::path root;  // the model's folder, canonical
  bool allow_outside = false;
  std::string refused;

  // Whether `file` may be read. A file outside that does not exist is only
  // not found (tinygltf also looks for a missing file in the working folder).
  bool permits(const fs::path& file) {
    if (allow_outside) return true;
    std::error_code ec;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(file, ec), ec);
    if (!ec && std::mismatch(root.begin(), root.end(), resolved.begin(), resolved.end()).first == root.end())
      return true;
    if (refused.empty() && fs::exists(file, ec)) refused = file.string();
    return false;
  }
  std::string refusal(const std::string& what, const std::string& file) const {
    return what + " names " + file + ", outside the model's folder " + root.string() +
           " (pass --allow-outside-paths to read files outside it)";
  }
};

// Filesystem callbacks for tinygltf: no shell-style path expansion (its
// default runs wordexp on URIs from the file), reads confined by FileAccess
// and a size limit on reads.
bool fs_file_exists(const std::string& path, void* access) {
  std::error_code ec;
  return static_cast<FileAccess*>(access)->permits(path) && fs::is_regular_file(path, ec);
}
std::string fs_expand_path(const std::string& path, void*) { return path; }
bool fs_read_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* access) {
  if (!static_cast<FileAccess*>(access)->permits(path)) {
    if (err) *err += "outside the model's folder: " + path + "\n";
    return false;
  }
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
  // The header's length is the file's, so the BIN chunk (the only chunk that
  // may come right after JSON) must start where the JSON chunk ends: when it
  // does not, it is the JSON chunk's length that is wrong.
  if (pos + 8 > size || read_le32(&b[pos + 4]) != 0x004E4942u) {  // "BIN\0"
    throw InputError(path, "GLB JSON chunk length is wrong: its " + std::to_string(json_length) + " bytes end at byte " +
                               std::to_string(pos) + ", where neither the file ends nor a BIN chunk header starts");
  }
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
// so syntax errors carry the parser's position and types can be checked; its
// estimated memory is charged to `memory` when given.
nlohmann::json parse_gltf_json(const std::string& path, const unsigned char* begin, const unsigned char* end,
                               MemoryBudget* memory) {
  const size_t bytes = static_cast<size_t>(end - begin);
  if (bytes > kMaxJsonBytes) {
    throw InputError(path, "glTF JSON is " + std::to_string(bytes) + " bytes, above the limit of " +
                               std::to_string(kMaxJsonBytes) + " bytes (" + MemoryBudget::format_bytes(kMaxJsonBytes) + ")");
  }
  // Parsed with the depth limit (tinygltf converts extras and extensions
  // recursively) and, with a budget, refused as soon as its values would not fit.
  JsonBuildOptions options;
  options.label = "glTF JSON";
  options.check_every = kJsonValuesPerCheck;
  auto check_count = [&](size_t values) {
    if (values > kMaxJsonValues)
      throw InputError(path, "glTF JSON holds more than " + std::to_string(kMaxJsonValues) +
                                 " values (numbers, strings, arrays, objects); geometry and images belong in buffers");
  };
  options.on_values = [&](size_t values) {
    check_count(values);
    if (memory)
      memory->require("glTF JSON (" + std::to_string(values) + " values so far)", path, "", values * kBytesPerJsonValue);
  };
  size_t values = 0;
  nlohmann::json doc = build_json(reinterpret_cast<const char*>(begin), reinterpret_cast<const char*>(end), path,
                                  options, &values);
  check_count(values);  // the last values since the parse's last check
  if (memory)
    memory->charge("glTF JSON (" + std::to_string(values) + " values)", path, "", values * kBytesPerJsonValue);
  return doc;
}

// A URI's path with its %XX escapes decoded (RFC 3986), as a file name.
std::string decode_uri_path(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// Every buffer has a uri but a GLB's buffer 0 (its BIN chunk; tinygltf gives
// that chunk to any buffer without one), and external buffer files are
// required: one that is absent is named here (tinygltf's own failure would
// only say the glTF is invalid).
void check_buffer_files(const std::string& path, const nlohmann::json& doc, const std::string& base_dir,
                        FileAccess& access, bool glb) {
  auto buffers = doc.find("buffers");
  if (buffers == doc.end()) return;
  for (size_t i = 0; i < buffers->size(); ++i) {
    auto uri = (*buffers)[i].find("uri");
    if (uri == (*buffers)[i].end()) {
      if (glb && i == 0) continue;
      throw InputError(path, "invalid glTF: 'buffers[" + std::to_string(i) +
                                 "]' has no uri; only buffer 0 of a GLB may leave it out (it is the BIN chunk)");
    }
    if (uri->get<std::string>().rfind("data:", 0) == 0) continue;
    const std::string name = decode_uri_path(uri->get<std::string>());
    const fs::path file = fs::path(base_dir) / name;
    if (!access.permits(file))
      throw InputError(path, access.refusal("buffers[" + std::to_string(i) + "].uri", file.string()));
    std::error_code ec;
    if (!fs::is_regular_file(fs::path(base_dir) / name, ec)) {
      throw InputError(path, "missing file: " + name + " (buffers[" + std::to_string(i) + "])");
    }
  }
}

// tinygltf 2.7 rejects a primitive whose indices accessor has no bufferView,
// which glTF allows (a Draco primitive's indices, sparse indices on zeros):
// such indices are taken out of the JSON it parses and put back on its model.
struct DetachedIndices {
  size_t mesh = 0;
  size_t primitive = 0;
  int accessor = -1;
};

std::vector<DetachedIndices> detach_dataless_indices(nlohmann::json& doc) {
  std::vector<DetachedIndices> out;
  if (!doc.contains("meshes") || !doc.contains("accessors")) return out;
  const nlohmann::json& accessors = doc["accessors"];
  nlohmann::json& meshes = doc["meshes"];
  for (size_t m = 0; m < meshes.size(); ++m) {
    nlohmann::json& primitives = meshes[m]["primitives"];
    for (size_t p = 0; p < primitives.size(); ++p) {
      auto it = primitives[p].find("indices");
      if (it == primitives[p].end()) continue;
      const uint64_t a = it->get<uint64_t>();
      if (a < accessors.size() && !accessors[a].contains("bufferView")) {
        out.push_back({m, p, static_cast<int>(a)});
        primitives[p].erase(it);
      }
    }
  }
  return out;
}

void restore_indices(tinygltf::Model& model, const std::vector<DetachedIndices>& detached) {
  for (const DetachedIndices& d : detached) {
    if (d.mesh < model.meshes.size() && d.primitive < model.meshes[d.mesh].primitives.size()) {
      model.meshes[d.mesh].primitives[d.primitive].indices = d.accessor;
    }
  }
}

// `glb` with its JSON chunk replaced by `json` (padded with spaces to 4
// bytes, as GLB requires) and its BIN chunk, if any, unchanged.
std::vector<unsigned char> glb_with_json(const std::vector<unsigned char>& glb, std::string json) {
  while (json.size() % 4 != 0) json += ' ';
  const size_t bin_start = 20 + read_le32(&glb[12]);
  const size_t length = 20 + json.size() + (glb.size() - bin_start);
  auto le32 = [](std::vector<unsigned char>& out, size_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
  };
  std::vector<unsigned char> out(glb.begin(), glb.begin() + 8);  // magic and version
  le32(out, length);
  le32(out, json.size());
  le32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), glb.begin() + static_cast<std::ptrdiff_t>(bin_start), glb.end());
  return out;
}

// Buffers by their declared lengths (tinygltf checks the data against them),
// held until the load ends alongside what is decoded from them.
void charge_buffers(const std::string& path, const nlohmann::json& doc, MemoryBudget& memory) {
  auto buffers = doc.find("buffers");
  if (buffers == doc.end()) return;
  for (size_t i = 0; i < buffers->size(); ++i) {
    const size_t bytes = (*buffers)[i]["byteLength"].get<size_t>();
    memory.charge("buffer " + std::to_string(i) + " (" + std::to_string(bytes) + " bytes)", path,
                  "buffers[" + std::to_string(i) + "]", bytes);
  }
}

// tinygltf leaves an image file it read as empty like one it could not find:
// without bytes. Such images are recorded as failures, not missing files.
void note_empty_image_files(const tinygltf::Model& model, const std::string& base_dir, ImageDecodeLog& log) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& img = model.images[i];
    if (!img.image.empty() || img.uri.empty() || img.uri.rfind("data:", 0) == 0) continue;
    std::error_code ec;
    const fs::path file = fs::path(base_dir) / decode_uri_path(img.uri);
    if (fs::is_regular_file(file, ec) && fs::file_size(file, ec) == 0) {
      log.failures.emplace(static_cast<int>(i), "the file is empty (0 bytes)");
    }
  }
}

// The scene's geometry, once built: its size follows from accessors that
// the charged buffers bound.
void charge_geometry(const std::string& path, const Scene& scene, MemoryBudget& memory) {
  size_t vertices = 0, triangles = 0, bytes = 0;
  for (const Mesh& mesh : scene.meshes) {
    for (const Primitive& p : mesh.primitives) {
      vertices += p.positions.size();
      triangles += p.triangle_count();
      bytes += p.positions.size() * sizeof(glm::vec3) + p.normals.size() * sizeof(glm::vec3) +
               p.tangents.size() * sizeof(glm::vec4) + p.texcoords.size() * sizeof(glm::vec2) +
               p.texcoords1.size() * sizeof(glm::vec2) + p.colors.size() * sizeof(glm::vec4) +
               p.indices.size() * sizeof(uint32_t);
    }
  }
  memory.charge("geometry (" + std::to_string(vertices) + " vertices, " + std::to_string(triangles) + " triangles)",
                path, "meshes", bytes);
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

  const std::string base_dir = fs::path(path).parent_path().string();
  FileAccess access;
  access.allow_outside = options.allow_outside_paths;
  std::error_code ec;
  access.root = fs::weakly_canonical(fs::absolute(base_dir.empty() ? fs::path(".") : fs::path(base_dir), ec), ec);
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fs_file_exists, &fs_expand_path, &fs_read_file, &fs_write_file, &access});
  ImageDecodeLog decode_log;
  loader.SetImageLoader(&capture_gltf_image, &decode_log);

  tinygltf::Model model;
  std::string err, warn;
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (glb) validate_glb_layout(path, bytes);
  const unsigned char* json = glb ? bytes.data() + 20 : bytes.data();
  nlohmann::json doc =
      parse_gltf_json(path, json, glb ? json + read_le32(&bytes[12]) : bytes.data() + bytes.size(), options.memory);
  validate_gltf_schema(path, doc);
  if (options.memory) charge_buffers(path, doc, *options.memory);
  const MeshoptDocument meshopt = prepare_meshopt_compression(path, doc);
  check_buffer_files(path, doc, base_dir, access, glb);
  const std::vector<DetachedIndices> detached = detach_dataless_indices(doc);
  if (meshopt.fallback_replaced || !detached.empty()) {
    const std::string edited = doc.dump();
    bytes = glb ? glb_with_json(bytes, edited) : std::vector<unsigned char>(edited.begin(), edited.end());
    if (bytes.size() > kMaxFileBytes) throw InputError(path, "glTF is above the size limit once edited for tinygltf");
  }
  const unsigned int size = static_cast<unsigned int>(bytes.size());
  const bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, base_dir)
                      : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                   size, base_dir);
  if (!access.refused.empty()) throw InputError(path, access.refusal("a URI", access.refused));
  if (!ok) throw InputError(path, "invalid glTF: " + one_line(err.empty() ? warn : err));
  restore_indices(model, detached);
  note_empty_image_files(model, base_dir, decode_log);
  if (model.asset.version.rfind("2.", 0) != 0) {
    throw InputError(path, "asset.version is \"" + model.asset.version + "\"; only glTF 2.x is supported");
  }

  GltfContext ctx{model, path};
  warn_unsupported_extensions(ctx);
  // Compressed data is decoded first, so everything below reads plain accessors.
  decode_meshopt_buffer_views(ctx, model, meshopt.views);
  decode_draco_primitives(ctx, model);
  Scene scene;
  scene.source = path;
  GltfMaterials materials = load_materials(ctx, decode_log, options);
  GltfMeshes meshes = load_meshes(ctx, materials.materials);
  scene.samplers = std::move(materials.samplers);
  scene.materials = std::move(materials.materials);
  scene.images = std::move(materials.images);
  scene.meshes = std::move(meshes.meshes);
  place_nodes(ctx, meshes, scene);
  if (options.memory) charge_geometry(path, scene, *options.memory);
  return scene;
}

}  // namespace cr

// A model's URIs name files inside its folder and subfolders only: "..",
// %2e%2e, absolute paths and symlinks out are refused with a message naming
// the URI's file, unless allow_outside_paths lets them through.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"

namespace fs = std::filesystem;

namespace {

// One triangle whose positions are in the buffer file `uri` (36 bytes), and,
// when image_uri is set, an image the model reads from that file.
std::string triangle_gltf(const std::string& uri, const std::string& image_uri = "") {
  std::string images = image_uri.empty() ? "" : R"(, "images": [{"uri": ")" + image_uri + R"("}])";
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": ")" + uri + R"(", "byteLength": 36}])" + images + "}";
}

void write_triangle_bin(const fs::path& p) {
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(v), sizeof v);
}

struct Tree {
  fs::path root = fs::temp_directory_path() / "cr_gltf_paths_test";
  fs::path model = root / "model";
  Tree() {
    fs::remove_all(root);
    fs::create_directories(model / "sub");
    write_triangle_bin(root / "secret.bin");
    write_triangle_bin(model / "sub" / "inside.bin");
    std::ofstream(root / "secret.png") << "not an image";
    std::error_code ec;
    fs::create_symlink(root / "secret.bin", model / "link.bin", ec);
  }
  ~Tree() { fs::remove_all(root); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(model / name) << text;
    return (model / name).string();
  }
};

std::string refusal(const std::string& path, const cr::GltfLoadOptions& options = {}) {
  try {
    (void)cr::load_gltf(path, options);
  } catch (const cr::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("glTF URIs: files outside the model's folder are refused unless allowed") {
  const Tree t;
  CHECK_NOTHROW((void)cr::load_gltf(t.write("inside.gltf", triangle_gltf("sub/inside.bin"))));
  CHECK_NOTHROW((void)cr::load_gltf(t.write("dots_inside.gltf", triangle_gltf("sub/../sub/inside.bin"))));
  for (const std::string& uri : std::vector<std::string>{"../secret.bin", "%2e%2e/secret.bin", "sub/../../secret.bin",
                                                         (t.root / "secret.bin").string()}) {
    CAPTURE(uri);
    const std::string path = t.write("outside.gltf", triangle_gltf(uri));
    const std::string e = refusal(path);
    CHECK(e.find("buffers[0].uri") != std::string::npos);
    CHECK(e.find("outside the model's folder") != std::string::npos);
    CHECK(e.find("secret.bin") != std::string::npos);
    if (fs::path(uri).is_absolute()) continue;  // tinygltf reads every URI relative to the model
    cr::GltfLoadOptions allow;
    allow.allow_outside_paths = true;
    CHECK(cr::load_gltf(path, allow).meshes.size() == 1);
  }
  // Outside and absent: still refused, by name.
  CHECK(refusal(t.write("absent.gltf", triangle_gltf("../absent.bin"))).find("absent.bin, outside") != std::string::npos);
  if (fs::is_symlink(t.model / "link.bin")) {
    const std::string e = refusal(t.write("link.gltf", triangle_gltf("link.bin")));
    CHECK(e.find("outside the model's folder") != std::string::npos);
  }
  // Images are read through the same checks.
  const std::string e = refusal(t.write("image.gltf", triangle_gltf("sub/inside.bin", "../secret.png")));
  CHECK(e.find("outside the model's folder") != std::string::npos);
  CHECK(e.find("secret.png") != std::string::npos);
}

// The memory a glTF load takes is estimated before it is allocated (issue 22,
// item 3): decoded images from their header sizes, buffers from their declared
// lengths, the parsed JSON from its values, so a small file that asks for
// gigabytes is refused at once against GltfLoadOptions::memory; and the JSON
// text itself has a size limit.
#include <filesystem>
#include <fstream>
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/core/memory_budget.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/gltf_rejection.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

constexpr size_t kGiB = size_t(1) << 30;

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = cr::test::test_output_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace

TEST_CASE("8 images sharing one 33-byte PNG header of 16384x16384 are refused before any is decoded") {
  // Each would decode to 1.33 GiB with its mips: under a 5 GiB limit three
  // fit, the fourth is refused. Nothing was decoded: the header-only PNG
  // would have failed as truncated.
  const std::string path = std::string(CR_TEST_DATA_DIR) + "/bad/huge_images_shared_uri.gltf";
  cr::MemoryBudget budget(5 * kGiB);
  cr::GltfLoadOptions options;
  options.memory = &budget;
  options.texture_decode_budget = 16 * kGiB;  // the memory limit decides, not the texture budget
  CHECK(cr::test::gltf_rejection(path, options) ==
        path + ": images[3] (image 3 (16384x16384 RGBA8 with mips)) needs 1.33 GiB, on top of 4.00 GiB already "
               "estimated, beyond the memory limit of 5.00 GiB (lower it in the file, or raise the limit with "
               "--memory-limit)");
  REQUIRE(budget.charges().size() == 5);
  CHECK(budget.charges()[1].field == "buffers[0]");
  CHECK(budget.charges()[1].bytes == 60);
  for (int i = 0; i < 3; ++i) {
    const cr::MemoryBudget::Charge& c = budget.charges()[2 + i];
    CHECK(c.field == "images[" + std::to_string(i) + "]");
    CHECK(c.what == "image " + std::to_string(i) + " (16384x16384 RGBA8 with mips)");
    CHECK(c.bytes == size_t(1431655764));  // 4 bytes x (16384^2 + 8192^2 + ... + 1)
  }
}

TEST_CASE("a loaded model's charges: JSON, buffers, images, geometry") {
  cr::test::GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int uv = b.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 0}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.add("textures", {{"source", 0}});
  b.add("images", {{"uri", cr::test::kFlatNormalPng}});
  cr::MemoryBudget budget(0);  // unlimited: charges are recorded
  cr::GltfLoadOptions options;
  options.memory = &budget;
  (void)cr::load_gltf(b.write("hardening_charges.gltf"), options);
  REQUIRE(budget.charges().size() == 4);
  CHECK(budget.charges()[0].what.rfind("glTF JSON (", 0) == 0);
  CHECK(budget.charges()[1].field == "buffers[0]");
  CHECK(budget.charges()[1].bytes == 60);
  CHECK(budget.charges()[2].field == "images[0]");
  CHECK(budget.charges()[2].what == "image 0 (1x1 RGBA8 with mips)");
  CHECK(budget.charges()[2].bytes == 4);
  CHECK(budget.charges()[3].field == "meshes");
  CHECK(budget.charges()[3].what == "geometry (3 vertices, 1 triangles)");
  CHECK(budget.charges()[3].bytes == 3 * (12 + 12 + 8) + 3 * 4);  // positions, normals, UVs; indices
}

TEST_CASE("a buffer's declared length is charged before tinygltf reads it") {
  cr::test::GltfBuilder b;
  b.doc["buffers"] = {{{"byteLength", 1500000000}, {"uri", "data:application/octet-stream;base64,AAAA"}}};
  const std::string path = b.write("hardening_huge_buffer.gltf");
  cr::MemoryBudget budget(kGiB);
  cr::GltfLoadOptions options;
  options.memory = &budget;
  CHECK(cr::test::gltf_rejection(path, options) ==
        path + ": buffers[0] (buffer 0 (1500000000 bytes)) needs 1.40 GiB, on top of 2 KiB already estimated, beyond "
               "the memory limit of 1.00 GiB (lower it in the file, or raise the limit with --memory-limit)");
}

TEST_CASE("the parsed JSON is estimated while it is parsed: 512k zeros in extras stop at the limit") {
  std::string text = R"({"asset": {"version": "2.0"}, "extras": [0)";
  for (int i = 1; i < (1 << 19); ++i) text += ",0";
  text += "]}";
  const std::string path = write_text("hardening_zeros_in_extras.gltf", text);
  cr::MemoryBudget budget(size_t(64) << 20);
  cr::GltfLoadOptions options;
  options.memory = &budget;
  CHECK(cr::test::gltf_rejection(path, options) ==
        path + ": glTF JSON (327680 values so far) needs 80.0 MiB beyond the memory limit of 64.0 MiB (lower it in "
               "the file, or raise the limit with --memory-limit)");
  CHECK(budget.total() == 0);
}

TEST_CASE("glTF JSON above 64 MiB is refused before it is parsed") {
  const std::string head = R"({"asset": {"version": "2.0"}})";
  const std::string path = write_text("hardening_json_above_cap.gltf", head + std::string((size_t(64) << 20) + 1 - head.size(), ' '));
  CHECK(cr::test::gltf_rejection(path) == path + ": glTF JSON is 67108865 bytes, above the limit of 67108864 bytes (64.0 MiB)");
  std::filesystem::remove(path);
}

TEST_CASE("glTF JSON of more than 2^22 values is refused while it is parsed") {
  // 30 million zeros in extras took 6 GB and 44 s to load under a large memory limit.
  std::string text = R"({"asset": {"version": "2.0"}, "extras": [)";
  const size_t zeros = (size_t(1) << 22) + 100;
  text.reserve(text.size() + 2 * zeros + 2);
  for (size_t i = 0; i < zeros; ++i) text += i ? ",0" : "0";
  text += "]}";
  const std::string path = write_text("hardening_json_values.gltf", text);
  CHECK(cr::test::gltf_rejection(path) ==
        path + ": glTF JSON holds more than 4194304 values (numbers, strings, arrays, objects); geometry and images "
               "belong in buffers");
  std::filesystem::remove(path);
}

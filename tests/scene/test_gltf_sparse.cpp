// Sparse accessors (core glTF 2.0): substitutes over a bufferView or over
// zeros, read by every accessor reader, and each malformed field rejected
// with one InputError naming it.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "engine/scene/gltf_loader.h"
#include "tests/khronos_assets.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

using cr::test::GltfBuilder;

// Three vertices of a triangle in the z = 0 plane, and its normals (given so
// that the loader keeps the vertices as they are).
const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const std::vector<float> kUpNormals = {0, 0, 1, 0, 0, 1, 0, 0, 1};

// A one-triangle glTF whose POSITION is accessor `position`.
void add_triangle_mesh(GltfBuilder& b, int position) {
  const int normals = b.floats(kUpNormals, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", position}, {"NORMAL", normals}}}}}}});
  b.add("nodes", {{"mesh", 0}});
}

nlohmann::json sparse_object(int count, int indices_view, int component_type, int values_view) {
  return {{"count", count},
          {"indices", {{"bufferView", indices_view}, {"componentType", component_type}}},
          {"values", {{"bufferView", values_view}}}};
}

// A triangle whose POSITION (accessor 0) is kTriangle with vertices
// `indices` replaced by `values` through a sparse accessor (UNSIGNED_SHORT indices).
GltfBuilder sparse_triangle(const std::vector<uint16_t>& indices, const std::vector<float>& values) {
  GltfBuilder b;
  const int position = b.floats(kTriangle, "VEC3", 3);
  const int indices_view = b.view(indices);
  const int values_view = b.view(values);
  b.doc["accessors"][position]["sparse"] = sparse_object(static_cast<int>(indices.size()), indices_view, 5123, values_view);
  add_triangle_mesh(b, position);
  return b;
}

glm::vec3 vertex(const std::vector<float>& v, size_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

template <typename T>
std::vector<T> read_le(const std::vector<char>& bytes, size_t offset, size_t count) {
  std::vector<T> out(count);
  std::memcpy(out.data(), bytes.data() + offset, count * sizeof(T));
  return out;
}

}  // namespace

TEST_CASE("sparse accessor over a bufferView: the named vertices move, the others keep the base data") {
  const std::vector<float> moved = {2, 3, 4};
  GltfBuilder b = sparse_triangle({1}, moved);
  const cr::Scene s = cr::load_gltf(b.write("sparse_over_view.gltf"));
  const cr::Primitive& p = s.meshes.at(0).primitives.at(0);
  REQUIRE(p.positions.size() == 3);
  CHECK(p.positions[0] == vertex(kTriangle, 0));
  CHECK(p.positions[1] == glm::vec3(2, 3, 4));
  CHECK(p.positions[2] == vertex(kTriangle, 2));
}

TEST_CASE("accessor without bufferView reads as zeros, with its sparse substitutes over them") {
  GltfBuilder b;
  const int values = b.view(std::vector<float>{1, 0, 0, 0, 1, 0});
  const int indices = b.view(std::vector<uint8_t>{1, 2});
  const int position = b.add("accessors", {{"componentType", 5126}, {"type", "VEC3"}, {"count", 3},
                                           {"sparse", sparse_object(2, indices, 5121, values)}});
  add_triangle_mesh(b, position);
  const cr::Scene s = cr::load_gltf(b.write("sparse_over_zeros.gltf"));
  const cr::Primitive& p = s.meshes.at(0).primitives.at(0);
  REQUIRE(p.positions.size() == 3);
  CHECK(p.positions[0] == glm::vec3(0.0f));
  CHECK(p.positions[1] == glm::vec3(1, 0, 0));
  CHECK(p.positions[2] == glm::vec3(0, 1, 0));
}

TEST_CASE("sparse index accessor: the index reader applies the substitutes") {
  GltfBuilder b;
  const int position = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  const int normals = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  // Base: two copies of triangle 0 1 2; the substitute turns the second into 0 2 3.
  const int idx = b.indices(std::vector<uint32_t>{0, 1, 2, 0, 1, 2});
  const int sparse_indices = b.view(std::vector<uint32_t>{4, 5});
  const int sparse_values = b.view(std::vector<uint32_t>{2, 3});
  b.doc["accessors"][idx]["sparse"] = sparse_object(2, sparse_indices, 5125, sparse_values);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", position}, {"NORMAL", normals}}}, {"indices", idx}}}}});
  b.add("nodes", {{"mesh", 0}});
  const cr::Scene s = cr::load_gltf(b.write("sparse_indices.gltf"));
  CHECK(s.meshes.at(0).primitives.at(0).indices == std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
}

TEST_CASE("SimpleSparseAccessor: the sparse accessor moves exactly the vertices it names (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf");
  if (!path) return;
  // The file's layout (SimpleSparseAccessor.gltf): 36 UNSIGNED_SHORT indices
  // at 0, 14 base positions at 72, 3 UNSIGNED_SHORT sparse indices at 240 and
  // their 3 positions at 248.
  std::ifstream in(std::filesystem::path(*path).parent_path() / "SimpleSparseAccessor.bin", std::ios::binary);
  const std::vector<char> bin{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  REQUIRE(bin.size() == 284);
  const std::vector<uint16_t> file_indices = read_le<uint16_t>(bin, 0, 36);
  const std::vector<float> base = read_le<float>(bin, 72, 14 * 3);
  const std::vector<uint16_t> sparse_indices = read_le<uint16_t>(bin, 240, 3);
  const std::vector<float> sparse_values = read_le<float>(bin, 248, 3 * 3);
  std::vector<float> expected = base;
  size_t moved = 0;
  for (size_t k = 0; k < sparse_indices.size(); ++k) {
    for (int c = 0; c < 3; ++c) expected[3 * sparse_indices[k] + c] = sparse_values[3 * k + c];
    moved += vertex(base, sparse_indices[k]) != vertex(sparse_values, k);
  }
  CHECK(moved == 3);  // every substitute differs from the base vertex it replaces

  const cr::Scene s = cr::load_gltf(*path);
  REQUIRE(s.meshes.size() == 1);
  const cr::Primitive& p = s.meshes[0].primitives.at(0);
  REQUIRE(p.indices.size() == file_indices.size());
  // Through the indices, so the comparison holds whether or not the loader
  // split vertices for the flat normals this model needs.
  for (size_t k = 0; k < file_indices.size(); ++k) {
    CAPTURE(k);
    CHECK(p.positions[p.indices[k]] == vertex(expected, file_indices[k]));
  }
  CHECK(s.bounds_min == glm::vec3(0.0f));
  CHECK(s.bounds_max == glm::vec3(6.0f, 4.0f, 0.0f));  // the accessor's declared max
}

TEST_CASE("malformed sparse accessors are rejected naming the field") {
  SUBCASE("index out of range") {
    expect_gltf_rejected(sparse_triangle({3}, {1, 1, 1}).write("sparse_index_out_of_range.gltf"),
                         "sparse.indices[0] = 3 is out of range for count 3");
  }
  SUBCASE("indices not increasing") {
    expect_gltf_rejected(sparse_triangle({2, 1}, {1, 1, 1, 2, 2, 2}).write("sparse_decreasing.gltf"),
                         "sparse.indices[1] = 1 does not follow 2 (indices must be strictly increasing)");
    expect_gltf_rejected(sparse_triangle({1, 1}, {1, 1, 1, 2, 2, 2}).write("sparse_repeated.gltf"),
                         "sparse.indices[1] = 1 does not follow 1");
  }
  SUBCASE("sparse count above the accessor's count, or zero") {
    expect_gltf_rejected(sparse_triangle({0, 1, 2, 2}, std::vector<float>(12, 1.0f)).write("sparse_count_too_big.gltf"),
                         "sparse.count 4 must be in [1, 3]");
    GltfBuilder b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["count"] = 0;
    expect_gltf_rejected(b.write("sparse_count_zero.gltf"), "sparse.count 0 must be in [1, 3]");
  }
  SUBCASE("index component type") {
    GltfBuilder b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["indices"]["componentType"] = 5126;
    expect_gltf_rejected(b.write("sparse_float_indices.gltf"),
                         "sparse.indices has component type FLOAT; expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  SUBCASE("index and value ranges outside their bufferViews") {
    GltfBuilder b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["values"]["byteOffset"] = 4;
    expect_gltf_rejected(b.write("sparse_values_past_view.gltf"),
                         "sparse.values (byteOffset 4, count 1, 12-byte elements) needs 16 bytes but bufferView");
    b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["count"] = 2;
    b.doc["accessors"][0]["sparse"]["values"]["bufferView"] = 0;  // the 36-byte base view: room for 2 values
    expect_gltf_rejected(b.write("sparse_indices_past_view.gltf"),
                         "sparse.indices (byteOffset 0, count 2, UNSIGNED_SHORT) needs 4 bytes but bufferView");
    b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["indices"]["bufferView"] = 9;
    expect_gltf_rejected(b.write("sparse_indices_view_out_of_range.gltf"), "has bufferView 9 out of range");
  }
  SUBCASE("wrong JSON types, caught before tinygltf reads them") {
    GltfBuilder b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"]["count"] = "1";
    expect_gltf_rejected(b.write("sparse_count_string.gltf"), "'accessors[0].sparse.count' must be a non-negative integer");
    b = sparse_triangle({1}, {1, 1, 1});
    b.doc["accessors"][0]["sparse"].erase("values");
    expect_gltf_rejected(b.write("sparse_no_values.gltf"), "'accessors[0].sparse.values' is required");
  }
  SUBCASE("an unused attribute is checked as strictly") {
    GltfBuilder b = sparse_triangle({1}, {1, 1, 1});
    const int custom = b.floats({1, 2, 3}, "SCALAR", 1);
    const int indices_view = b.view(std::vector<uint16_t>{5});
    const int values_view = b.view(std::vector<float>{9});
    b.doc["accessors"][custom]["sparse"] = sparse_object(1, indices_view, 5123, values_view);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["_CUSTOM"] = custom;
    expect_gltf_rejected(b.write("sparse_unused_attribute.gltf"), "attribute _CUSTOM: accessor 2 sparse.indices[0] = 5 is out of range");
  }
  SUBCASE("zeros beyond the size limit of an accessor without bufferView") {
    GltfBuilder b;
    const int position = b.add("accessors", {{"componentType", 5126}, {"type", "VEC3"}, {"count", 1 << 27}});
    add_triangle_mesh(b, position);
    expect_gltf_rejected(b.write("zeros_too_big.gltf"), "bytes of zeros are above the limit");
  }
}

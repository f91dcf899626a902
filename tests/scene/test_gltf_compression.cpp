// Quantized and compressed glTF geometry: KHR_mesh_quantization's integer
// attributes, KHR_draco_mesh_compression and EXT_meshopt_compression, each
// loading to the geometry of its uncompressed source, and each malformed
// field rejected with one InputError naming it. Also the message for a
// missing external buffer file.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <glm/glm.hpp>
#include <meshoptimizer.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_accessors.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/gltf_meshopt.h"
#include "tests/khronos_assets.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

using cr::test::GltfBuilder;

glm::vec3 extent(const cr::Scene& s) { return s.bounds_max - s.bounds_min; }

float max_component(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// Largest difference of the world bounds of two scenes, per axis.
float bounds_difference(const cr::Scene& a, const cr::Scene& b) {
  return max_component(glm::max(glm::abs(a.bounds_min - b.bounds_min), glm::abs(a.bounds_max - b.bounds_max)));
}

// Drawn triangles with three distinct corners. Draco's encoder drops the
// others (assimp's 2CylinderEngine loses 10419 of them: 10413 with a repeated
// index, 6 with two equal corners).
size_t proper_triangle_count(const cr::Scene& s) {
  size_t n = 0;
  for (const cr::Draw& d : s.draws) {
    const cr::Primitive& p = s.primitive(d);
    for (size_t t = 0; t < p.indices.size(); t += 3) {
      const glm::vec3& a = p.positions[p.indices[t]];
      const glm::vec3& b = p.positions[p.indices[t + 1]];
      const glm::vec3& c = p.positions[p.indices[t + 2]];
      n += a != b && b != c && a != c;
    }
  }
  return n;
}

// A compressed or quantized variant against its plain source: the same
// draws, the source's triangles less its degenerate ones, and world bounds
// within `tolerance` of the source's largest extent.
void check_variant_matches_plain(const std::string& plain_path, const std::string& variant_path, float tolerance) {
  const cr::Scene plain = cr::load_gltf(plain_path);
  const cr::Scene variant = cr::load_gltf(variant_path);
  CAPTURE(variant_path);
  CHECK(variant.draws.size() == plain.draws.size());
  CHECK(variant.triangle_count() == proper_triangle_count(plain));
  const float size = max_component(extent(plain));
  const float diff = bounds_difference(plain, variant);
  MESSAGE(variant_path << ": " << variant.triangle_count() << " triangles (plain: " << plain.triangle_count()
                       << "); world bounds differ from the plain variant by " << diff << " (" << diff / size
                       << " of its extent " << size << ")");
  CHECK(diff <= tolerance * size);
}

// The 12 triangles of an axis-aligned cube of edge `size`, as 3 corners each.
std::vector<std::array<glm::vec3, 3>> cube_triangles(float size) {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  cr::test::unit_cube(positions, indices);
  std::vector<std::array<glm::vec3, 3>> out;
  for (size_t t = 0; t < indices.size(); t += 3) {
    std::array<glm::vec3, 3> tri;
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = indices[t + c];
      tri[c] = size * glm::vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    }
    out.push_back(tri);
  }
  return out;
}

std::vector<std::array<glm::vec3, 3>> triangles_of(const cr::Primitive& p) {
  std::vector<std::array<glm::vec3, 3>> out;
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    out.push_back({p.positions[p.indices[t]], p.positions[p.indices[t + 1]], p.positions[p.indices[t + 2]]});
  }
  return out;
}

// Whether every triangle of `got` is one of `expected` (corners within
// `tolerance`, same winding, any starting corner), and the counts agree.
bool same_triangles(const std::vector<std::array<glm::vec3, 3>>& got,
                    const std::vector<std::array<glm::vec3, 3>>& expected, float tolerance) {
  if (got.size() != expected.size()) return false;
  auto near = [tolerance](const glm::vec3& a, const glm::vec3& b) { return max_component(glm::abs(a - b)) <= tolerance; };
  for (const auto& g : got) {
    bool found = false;
    for (const auto& e : expected) {
      for (int r = 0; r < 3 && !found; ++r) {
        found = near(g[0], e[r]) && near(g[1], e[(r + 1) % 3]) && near(g[2], e[(r + 2) % 3]);
      }
    }
    if (!found) return false;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------
// KHR_mesh_quantization

namespace {

// One triangle with POSITION as SHORT (not normalized), a flat normal, and
// TEXCOORD_0 of the given encoding.
template <typename T>
GltfBuilder quantized_triangle(const std::vector<T>& uv, int component_type, bool normalized) {
  GltfBuilder b;
  const int position = b.add("accessors", {{"bufferView", b.view(std::vector<int16_t>{0, 0, 0, -1000, 0, 0, 0, -1000, 0})},
                                           {"componentType", 5122}, {"type", "VEC3"}, {"count", 3}});
  // BYTE normalized normals padded to a 4-byte stride, as gltfpack writes them.
  const int normal_view = b.view(std::vector<int8_t>{0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0});
  b.doc["bufferViews"][normal_view]["byteStride"] = 4;
  const int normal = b.add("accessors", {{"bufferView", normal_view}, {"componentType", 5120}, {"normalized", true},
                                         {"type", "VEC3"}, {"count", 3}});
  const int texcoord = b.add("accessors", {{"bufferView", b.view(uv)}, {"componentType", component_type},
                                           {"normalized", normalized}, {"type", "VEC2"}, {"count", 3}});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", position}, {"NORMAL", normal}, {"TEXCOORD_0", texcoord}}}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  return b;
}

std::vector<glm::vec2> loaded_texcoords(GltfBuilder b, const std::string& name) {
  const cr::Scene s = cr::load_gltf(b.write(name));
  const cr::Primitive& p = s.meshes.at(0).primitives.at(0);
  CHECK(p.positions == std::vector<glm::vec3>{{0, 0, 0}, {-1000, 0, 0}, {0, -1000, 0}});
  CHECK(p.normals == std::vector<glm::vec3>(3, glm::vec3(0, 0, 1)));
  return p.texcoords;
}

}  // namespace

TEST_CASE("KHR_mesh_quantization: integer attributes convert by the spec's rules") {
  // snorm: max(c / 127, -1), so -128 and -127 are both -1.
  CHECK(loaded_texcoords(quantized_triangle(std::vector<int8_t>{-128, -127, 127, 64, 0, 1}, 5120, true), "q_byte_norm.gltf") ==
        std::vector<glm::vec2>{{-1.0f, -1.0f}, {1.0f, 64 / 127.0f}, {0.0f, 1 / 127.0f}});
  CHECK(loaded_texcoords(quantized_triangle(std::vector<int16_t>{-32768, 32767, 16384, 0, -1, 2}, 5122, true), "q_short_norm.gltf") ==
        std::vector<glm::vec2>{{-1.0f, 1.0f}, {16384 / 32767.0f, 0.0f}, {-1 / 32767.0f, 2 / 32767.0f}});
  // unorm: c / 255 and c / 65535.
  CHECK(loaded_texcoords(quantized_triangle(std::vector<uint8_t>{255, 0, 128, 1, 0, 0}, 5121, true), "q_ubyte_norm.gltf") ==
        std::vector<glm::vec2>{{1.0f, 0.0f}, {128 / 255.0f, 1 / 255.0f}, {0.0f, 0.0f}});
  CHECK(loaded_texcoords(quantized_triangle(std::vector<uint16_t>{65535, 0, 32768, 1, 0, 0}, 5123, true), "q_ushort_norm.gltf") ==
        std::vector<glm::vec2>{{1.0f, 0.0f}, {32768 / 65535.0f, 1 / 65535.0f}, {0.0f, 0.0f}});
  // Not normalized: the integer's value.
  CHECK(loaded_texcoords(quantized_triangle(std::vector<uint8_t>{200, 0, 1, 2, 3, 4}, 5121, false), "q_ubyte.gltf") ==
        std::vector<glm::vec2>{{200, 0}, {1, 2}, {3, 4}});
  CHECK(loaded_texcoords(quantized_triangle(std::vector<int16_t>{-300, 0, 1, 2, 3, 4}, 5122, false), "q_short.gltf") ==
        std::vector<glm::vec2>{{-300, 0}, {1, 2}, {3, 4}});
}

TEST_CASE("KHR_mesh_quantization: quantized types are read without the extension declared") {
  GltfBuilder b = quantized_triangle(std::vector<uint16_t>{0, 0, 1, 1, 2, 2}, 5123, false);
  b.doc.erase("extensionsUsed");
  b.doc.erase("extensionsRequired");
  CHECK(loaded_texcoords(b, "q_undeclared.gltf") == std::vector<glm::vec2>{{0, 0}, {1, 1}, {2, 2}});
}

TEST_CASE("KHR_mesh_quantization: component types outside the allowed set are rejected, naming the set") {
  GltfBuilder b = quantized_triangle(std::vector<uint16_t>{0, 0, 1, 1, 2, 2}, 5123, false);
  b.doc["accessors"][1]["normalized"] = false;
  expect_gltf_rejected(b.write("q_normal_not_normalized.gltf"),
                       "NORMAL: accessor 1 has component type BYTE (not normalized); expected FLOAT, normalized BYTE, "
                       "normalized SHORT");
  b = quantized_triangle(std::vector<uint32_t>{0, 0, 1, 1, 2, 2}, 5125, false);
  expect_gltf_rejected(b.write("q_texcoord_uint.gltf"),
                       "TEXCOORD_0: accessor 2 has component type UNSIGNED_INT (not normalized); expected FLOAT, BYTE "
                       "(normalized or not), UNSIGNED_BYTE (normalized or not), SHORT (normalized or not), "
                       "UNSIGNED_SHORT (normalized or not)");
  b = quantized_triangle(std::vector<uint16_t>{0, 0, 1, 1, 2, 2}, 5123, false);
  b.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 1;  // BYTE normalized: snorm colours are not allowed
  expect_gltf_rejected(b.write("q_color_byte.gltf"),
                       "COLOR_0: accessor 1 has component type BYTE (normalized); expected FLOAT, normalized "
                       "UNSIGNED_BYTE, normalized UNSIGNED_SHORT");
}

TEST_CASE("KHR_mesh_quantization: quantized Duck and Avocado match their plain variants in world space (CR_ASSETS_DIR)") {
  // Their positions are 14-bit integers (max 16383) dequantized by the node
  // transform, so a bound moves by at most one step, 1/16383 of the extent:
  // 1e-4 of the extent is that step with room for float rounding.
  for (const char* model : {"Duck", "Avocado"}) {
    const auto plain = cr::test::asset_path(std::string("khronos/") + model + "/glTF/" + model + ".gltf");
    const auto quantized = cr::test::asset_path(std::string("khronos/") + model + "/glTF-Quantized/" + model + ".gltf");
    if (!plain || !quantized) continue;
    check_variant_matches_plain(*plain, *quantized, 1e-4f);
  }
}

TEST_CASE("JOINTS_n: UNSIGNED_BYTE and UNSIGNED_SHORT joint indices, with sparse substitutes; other types rejected") {
  // On a model built here: the reader serves skins, which load_gltf reads elsewhere.
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  buffer.data = {1, 2, 3, 4, 5, 6, 7, 8,                // 2 x VEC4 UNSIGNED_BYTE at 0
                 0x34, 0x12, 0, 0, 1, 0, 0xFF, 0xFF,  // 1 x VEC4 UNSIGNED_SHORT at 8
                 1, 0, 0, 0, 9, 9, 9, 9};             // sparse: index 1 (UNSIGNED_INT) at 16, VEC4 UNSIGNED_BYTE at 20
  model.buffers.push_back(buffer);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteLength = buffer.data.size();
  model.bufferViews.push_back(view);
  tinygltf::Accessor bytes;
  bytes.bufferView = 0;
  bytes.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  bytes.type = TINYGLTF_TYPE_VEC4;
  bytes.count = 2;
  tinygltf::Accessor shorts = bytes;
  shorts.byteOffset = 8;
  shorts.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  shorts.count = 1;
  tinygltf::Accessor sparse = bytes;
  sparse.sparse.isSparse = true;
  sparse.sparse.count = 1;
  sparse.sparse.indices = {16, 0, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
  sparse.sparse.values = {0, 20};
  tinygltf::Accessor normalized = bytes;
  normalized.normalized = true;
  tinygltf::Accessor vec3 = bytes;
  vec3.type = TINYGLTF_TYPE_VEC3;
  model.accessors = {bytes, shorts, sparse, normalized, vec3};
  const cr::GltfContext ctx{model, "joints.gltf"};
  CHECK(cr::read_joints_accessor(ctx, 0, "JOINTS_0") == std::vector<glm::u16vec4>{{1, 2, 3, 4}, {5, 6, 7, 8}});
  CHECK(cr::read_joints_accessor(ctx, 1, "JOINTS_0") == std::vector<glm::u16vec4>{{0x1234, 0, 1, 0xFFFF}});
  CHECK(cr::read_joints_accessor(ctx, 2, "JOINTS_0") == std::vector<glm::u16vec4>{{1, 2, 3, 4}, {9, 9, 9, 9}});
  CHECK_THROWS_WITH_AS(cr::read_joints_accessor(ctx, 3, "JOINTS_0"),
                       "joints.gltf: JOINTS_0: accessor 3 has component type UNSIGNED_BYTE (normalized); joints must be "
                       "UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized",
                       cr::InputError);
  CHECK_THROWS_WITH_AS(cr::read_joints_accessor(ctx, 4, "JOINTS_0"),
                       "joints.gltf: JOINTS_0: accessor 4 has type VEC3; joints must be VEC4", cr::InputError);
}

// ---------------------------------------------------------------------------
// KHR_draco_mesh_compression

TEST_CASE("KHR_draco_mesh_compression: Khronos and assimp Draco models match their plain variants") {
  // gltf-pipeline's default position quantization is 11 bits (Box's declared
  // max is 0.5004885 for 0.5: one step of 1/2047 over a unit extent), so a
  // bound moves by at most about one step, 4.9e-4 of the extent; 1e-3 allows
  // two steps.
  const std::string assimp = CR_ASSIMP_GLTF_DIR;
  check_variant_matches_plain(assimp + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                              assimp + "/draco/2CylinderEngine.gltf", 1e-3f);
  for (const char* model : {"Box", "Duck", "Avocado", "WaterBottle", "CesiumMilkTruck", "MorphPrimitivesTest"}) {
    const auto plain = cr::test::asset_path(std::string("khronos/") + model + "/glTF/" + model + ".gltf");
    const auto draco = cr::test::asset_path(std::string("khronos/") + model + "/glTF-Draco/" + model + ".gltf");
    if (!plain || !draco) continue;
    check_variant_matches_plain(*plain, *draco, 1e-3f);
  }
}

namespace {

// Draco streams made here with Debian's encoder: a cube's triangles with
// POSITION (attribute id 0, 14-bit) and per-face NORMAL (id 1, 10-bit).
struct DracoCube {
  std::vector<uint8_t> bytes;
  size_t points = 0;
  size_t triangles = 0;
};

DracoCube encode_draco_cube(float size) {
  const std::vector<std::array<glm::vec3, 3>> tris = cube_triangles(size);
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(static_cast<int>(tris.size()));
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nrm = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  for (size_t t = 0; t < tris.size(); ++t) {
    const glm::vec3 n = glm::normalize(glm::cross(tris[t][1] - tris[t][0], tris[t][2] - tris[t][0]));
    const draco::FaceIndex f(static_cast<uint32_t>(t));
    builder.SetAttributeValuesForFace(pos, f, &tris[t][0], &tris[t][1], &tris[t][2]);
    builder.SetAttributeValuesForFace(nrm, f, &n, &n, &n);
  }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  REQUIRE(mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  draco::EncoderBuffer buffer;
  REQUIRE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
  DracoCube out;
  out.bytes.assign(buffer.data(), buffer.data() + buffer.size());
  out.points = mesh->num_points();
  out.triangles = mesh->num_faces();
  return out;
}

// Accessors as a Draco primitive declares them: count, type, no data.
int draco_accessor(GltfBuilder& b, int component_type, const char* type, size_t count) {
  return b.add("accessors", {{"componentType", component_type}, {"type", type}, {"count", count}});
}

nlohmann::json draco_primitive(int view, int indices, int position, int normal) {
  return {{"attributes", {{"POSITION", position}, {"NORMAL", normal}}},
          {"indices", indices},
          {"extensions",
           {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}}}}};
}

// A one-primitive glTF of `cube`.
GltfBuilder draco_cube_gltf(const DracoCube& cube) {
  GltfBuilder b;
  const int view = b.view(cube.bytes);
  const int indices = draco_accessor(b, 5123, "SCALAR", cube.triangles * 3);
  const int position = draco_accessor(b, 5126, "VEC3", cube.points);
  const int normal = draco_accessor(b, 5126, "VEC3", cube.points);
  b.add("meshes", {{"primitives", {draco_primitive(view, indices, position, normal)}}});
  b.add("nodes", {{"mesh", 0}});
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return b;
}

// 14-bit positions over the cube's extent `size`: a corner moves by at most
// half a step (size / 32766); one step leaves room for float rounding.
float draco_tolerance(float size) { return size / 16383.0f; }

}  // namespace

TEST_CASE("KHR_draco_mesh_compression: a cube encoded here decodes to its triangles") {
  const DracoCube cube = encode_draco_cube(0.7f);
  const cr::Scene s = cr::load_gltf(draco_cube_gltf(cube).write("draco_cube.gltf"));
  const cr::Primitive& p = s.meshes.at(0).primitives.at(0);
  CHECK(p.positions.size() == cube.points);
  CHECK(same_triangles(triangles_of(p), cube_triangles(0.7f), draco_tolerance(0.7f)));
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    const glm::vec3 face = glm::normalize(glm::cross(p.positions[p.indices[t + 1]] - p.positions[p.indices[t]],
                                                     p.positions[p.indices[t + 2]] - p.positions[p.indices[t]]));
    CHECK(glm::dot(p.normals[p.indices[t]], face) > 0.999f);  // 10-bit normals, decoded per vertex
  }
}

TEST_CASE("KHR_draco_mesh_compression: accessors shared between primitives are not overwritten") {
  const DracoCube small = encode_draco_cube(1.0f);
  const DracoCube big = encode_draco_cube(2.0f);
  REQUIRE(small.points == big.points);
  SUBCASE("two Draco primitives on one declared accessor each get their own data") {
    GltfBuilder b = draco_cube_gltf(small);
    const int big_view = b.view(big.bytes);
    b.doc["meshes"][0]["primitives"].push_back(draco_primitive(big_view, 0, 1, 2));
    const cr::Scene s = cr::load_gltf(b.write("draco_shared_declared.gltf"));
    const cr::Mesh& m = s.meshes.at(0);
    REQUIRE(m.primitives.size() == 2);
    CHECK(same_triangles(triangles_of(m.primitives[0]), cube_triangles(1.0f), draco_tolerance(1.0f)));
    CHECK(same_triangles(triangles_of(m.primitives[1]), cube_triangles(2.0f), draco_tolerance(2.0f)));
  }
  SUBCASE("a plain primitive keeps the fallback data of an accessor a Draco primitive also names") {
    // Fallback data (here deliberately not the Draco content: a 3x cube) in
    // the declared POSITION accessor, which a plain primitive also reads.
    GltfBuilder b = draco_cube_gltf(small);
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    cr::test::unit_cube(positions, indices);
    for (float& v : positions) v *= 3.0f;
    REQUIRE(positions.size() / 3 == small.points);
    b.doc["accessors"][1]["bufferView"] = b.view(positions);
    b.doc["extensionsRequired"] = nlohmann::json::array();
    const int plain_indices = b.indices(indices);
    b.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 1}}}, {"indices", plain_indices}});
    const cr::Scene s = cr::load_gltf(b.write("draco_shared_fallback.gltf"));
    const cr::Mesh& m = s.meshes.at(0);
    REQUIRE(m.primitives.size() == 2);
    CHECK(same_triangles(triangles_of(m.primitives[0]), cube_triangles(1.0f), draco_tolerance(1.0f)));
    CHECK(same_triangles(triangles_of(m.primitives[1]), cube_triangles(3.0f), 0.0f));  // the file's floats, exactly
  }
}

TEST_CASE("KHR_draco_mesh_compression: malformed data and mismatched accessors are rejected") {
  const DracoCube cube = encode_draco_cube(1.0f);
  const std::string count = std::to_string(cube.points);
  SUBCASE("data that does not decode") {
    GltfBuilder b = draco_cube_gltf(cube);
    b.doc["bufferViews"][0]["byteLength"] = cube.bytes.size() / 2;
    expect_gltf_rejected(b.write("draco_truncated.gltf"), "the KHR_draco_mesh_compression data in bufferView 0 does not decode (");
    DracoCube garbage = cube;
    std::fill(garbage.bytes.begin(), garbage.bytes.begin() + 8, uint8_t(0x5A));
    expect_gltf_rejected(draco_cube_gltf(garbage).write("draco_garbage.gltf"), "does not decode");
  }
  SUBCASE("declared counts that differ from the decoded data") {
    GltfBuilder b = draco_cube_gltf(cube);
    b.doc["accessors"][1]["count"] = cube.points + 1;
    expect_gltf_rejected(b.write("draco_position_count.gltf"),
                         "attribute POSITION: accessor 1 declares count " + std::to_string(cube.points + 1) +
                             " but the Draco data has " + count + " vertices");
    b = draco_cube_gltf(cube);
    b.doc["accessors"][0]["count"] = 33;
    expect_gltf_rejected(b.write("draco_index_count.gltf"), "indices: accessor 0 declares count 33 but the Draco data has 12 triangles");
  }
  SUBCASE("types that differ from the decoded data") {
    GltfBuilder b = draco_cube_gltf(cube);
    b.doc["accessors"][1]["type"] = "VEC2";
    expect_gltf_rejected(b.write("draco_position_vec2.gltf"), "accessor 1 declares VEC2 but Draco attribute 0 has 3 components");
    b = draco_cube_gltf(cube);
    b.doc["accessors"][1]["componentType"] = 5123;
    expect_gltf_rejected(b.write("draco_position_ushort.gltf"),
                         "accessor 1 declares UNSIGNED_SHORT but Draco attribute 0 stores FLOAT");
    b = draco_cube_gltf(cube);
    b.doc["accessors"][0]["componentType"] = 5121;  // 24 vertices fit in bytes: accepted
    CHECK(cr::load_gltf(b.write("draco_byte_indices.gltf")).triangle_count() == 12);
  }
  SUBCASE("attribute ids and names") {
    GltfBuilder b = draco_cube_gltf(cube);
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["NORMAL"] = 5;
    expect_gltf_rejected(b.write("draco_missing_id.gltf"), "attribute NORMAL: the Draco data has no attribute with id 5");
    b = draco_cube_gltf(cube);
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["TEXCOORD_0"] = 2;
    expect_gltf_rejected(b.write("draco_unknown_semantic.gltf"),
                         "names attribute TEXCOORD_0, which the primitive does not have");
  }
  SUBCASE("the extension object and the primitive") {
    GltfBuilder b = draco_cube_gltf(cube);
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 7;
    expect_gltf_rejected(b.write("draco_view_out_of_range.gltf"), "has bufferView 7 out of range");
    b = draco_cube_gltf(cube);
    b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = "0";
    expect_gltf_rejected(b.write("draco_view_string.gltf"), "KHR_draco_mesh_compression.bufferView must be a non-negative integer");
    b = draco_cube_gltf(cube);
    b.doc["meshes"][0]["primitives"][0]["mode"] = 5;
    expect_gltf_rejected(b.write("draco_strip.gltf"), "uses KHR_draco_mesh_compression with mode 5; only TRIANGLES (4) is decoded");
  }
}

// ---------------------------------------------------------------------------
// EXT_meshopt_compression

namespace {

// Compressed streams and the glTF that points at them: buffer 0 holds the
// streams, buffer 1 is the fallback the extension's views belong to.
class MeshoptAsset {
 public:
  GltfBuilder b;

  // A bufferView of count * stride bytes in the fallback buffer whose
  // extension object points at `stream`; returns its index.
  int compressed_view(const std::vector<uint8_t>& stream, size_t count, size_t stride, const char* mode,
                      const char* filter, size_t parent_stride) {
    const size_t offset = bin_.size();
    bin_.insert(bin_.end(), stream.begin(), stream.end());
    while (bin_.size() % 4) bin_.push_back(0);
    nlohmann::json view = {{"buffer", 1}, {"byteOffset", fallback_size_}, {"byteLength", count * stride},
                           {"extensions",
                            {{"EXT_meshopt_compression",
                              {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", stream.size()}, {"byteStride", stride},
                               {"count", count}, {"mode", mode}, {"filter", filter}}}}}};
    if (parent_stride) view["byteStride"] = parent_stride;
    fallback_size_ += count * stride;
    return b.add("bufferViews", view);
  }

  // Writes .gltf (streams as a data URI) or .glb (streams as the BIN chunk);
  // the fallback buffer has no uri and no data either way.
  std::string write(const std::string& name, bool glb) {
    nlohmann::json doc = b.doc;
    nlohmann::json fallback = {{"byteLength", fallback_size_}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
    nlohmann::json streams = {{"byteLength", bin_.size()}};
    if (!glb) streams["uri"] = "data:application/octet-stream;base64," + cr::test::base64(bin_);
    doc["buffers"] = {streams, fallback};
    doc["extensionsUsed"] = {"EXT_meshopt_compression"};
    doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    const std::string path = cr::test::test_output_dir() + "/" + name;
    std::ofstream out(path, std::ios::binary);
    if (!glb) {
      out << doc.dump(1);
      return path;
    }
    std::string json = doc.dump();
    while (json.size() % 4) json += ' ';
    std::vector<uint8_t> glb_bytes;
    auto le32 = [&glb_bytes](size_t v) {
      for (int k = 0; k < 4; ++k) glb_bytes.push_back(static_cast<uint8_t>(v >> (8 * k)));
    };
    glb_bytes.insert(glb_bytes.end(), {'g', 'l', 'T', 'F'});
    le32(2);
    le32(12 + 8 + json.size() + 8 + bin_.size());
    le32(json.size());
    le32(0x4E4F534Au);  // "JSON"
    glb_bytes.insert(glb_bytes.end(), json.begin(), json.end());
    le32(bin_.size());
    le32(0x004E4942u);  // "BIN"
    glb_bytes.insert(glb_bytes.end(), bin_.begin(), bin_.end());
    out.write(reinterpret_cast<const char*>(glb_bytes.data()), static_cast<std::streamsize>(glb_bytes.size()));
    return path;
  }

 private:
  std::vector<uint8_t> bin_;
  size_t fallback_size_ = 0;
};

template <typename T>
std::vector<uint8_t> encode_vertices(const std::vector<T>& data, size_t count, size_t stride) {
  std::vector<uint8_t> out(meshopt_encodeVertexBufferBound(count, stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data.data(), count, stride));
  return out;
}

std::vector<uint8_t> encode_triangles(const std::vector<uint32_t>& indices, size_t vertices) {
  std::vector<uint8_t> out(meshopt_encodeIndexBufferBound(indices.size(), vertices));
  out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), indices.size()));
  return out;
}

std::vector<uint8_t> encode_index_sequence(const std::vector<uint32_t>& indices, size_t vertices) {
  std::vector<uint8_t> out(meshopt_encodeIndexSequenceBound(indices.size(), vertices));
  out.resize(meshopt_encodeIndexSequence(out.data(), out.size(), indices.data(), indices.size()));
  return out;
}

// The unit cube as gltfpack would write it: float positions (ATTRIBUTES),
// normals through the OCTAHEDRAL filter as 8-bit snorm with a 4-byte stride,
// and its indices twice, as a TRIANGLES stream (UNSIGNED_INT) for primitive 0
// and an INDICES stream (UNSIGNED_SHORT) for primitive 1.
struct MeshoptCube {
  std::vector<float> positions;
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> indices;
  MeshoptAsset asset;
};

MeshoptCube meshopt_cube() {
  MeshoptCube c;
  cr::test::unit_cube(c.positions, c.indices);
  const size_t n = c.positions.size() / 3;
  auto position = [&c](uint32_t v) { return glm::vec3(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]); };
  c.normals.resize(n);  // per face: each vertex of unit_cube belongs to one face
  for (size_t t = 0; t < c.indices.size(); t += 3) {
    const uint32_t* i = &c.indices[t];
    const glm::vec3 normal = glm::normalize(glm::cross(position(i[1]) - position(i[0]), position(i[2]) - position(i[0])));
    for (int k = 0; k < 3; ++k) c.normals[i[k]] = normal;
  }
  std::vector<float> normals4(4 * n, 0.0f);  // the filter's input: xyz and w per vector
  for (size_t v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) normals4[4 * v + k] = c.normals[v][k];
  }
  std::vector<int8_t> oct(4 * n);
  meshopt_encodeFilterOct(oct.data(), n, 4, 8, normals4.data());

  MeshoptAsset& m = c.asset;
  const int pos_view = m.compressed_view(encode_vertices(c.positions, n, 12), n, 12, "ATTRIBUTES", "NONE", 12);
  const int nrm_view = m.compressed_view(encode_vertices(oct, n, 4), n, 4, "ATTRIBUTES", "OCTAHEDRAL", 4);
  const int tri_view = m.compressed_view(encode_triangles(c.indices, n), c.indices.size(), 4, "TRIANGLES", "NONE", 0);
  const int seq_view = m.compressed_view(encode_index_sequence(c.indices, n), c.indices.size(), 2, "INDICES", "NONE", 0);
  const int pos = m.b.add("accessors", {{"bufferView", pos_view}, {"componentType", 5126}, {"type", "VEC3"}, {"count", n}});
  const int nrm = m.b.add("accessors", {{"bufferView", nrm_view}, {"componentType", 5120}, {"normalized", true},
                                        {"type", "VEC3"}, {"count", n}});
  const int tri = m.b.add("accessors", {{"bufferView", tri_view}, {"componentType", 5125}, {"type", "SCALAR"},
                                        {"count", c.indices.size()}});
  const int seq = m.b.add("accessors", {{"bufferView", seq_view}, {"componentType", 5123}, {"type", "SCALAR"},
                                        {"count", c.indices.size()}});
  const nlohmann::json attributes = {{"POSITION", pos}, {"NORMAL", nrm}};
  m.b.add("meshes", {{"primitives", {{{"attributes", attributes}, {"indices", tri}}, {{"attributes", attributes}, {"indices", seq}}}}});
  m.b.add("nodes", {{"mesh", 0}});
  return c;
}

nlohmann::json& meshopt_of(GltfBuilder& b, int view) { return b.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]; }

}  // namespace

TEST_CASE("EXT_meshopt_compression: a cube encoded here loads as the original geometry, from .gltf and .glb") {
  for (bool glb : {false, true}) {
    MeshoptCube c = meshopt_cube();
    const cr::Scene s = cr::load_gltf(c.asset.write(glb ? "meshopt_cube.glb" : "meshopt_cube.gltf", glb));
    CAPTURE(glb);
    const cr::Mesh& m = s.meshes.at(0);
    REQUIRE(m.primitives.size() == 2);
    for (const cr::Primitive& p : m.primitives) {
      // Positions and indices are lossless; octahedral 8-bit normals are within a few snorm steps.
      REQUIRE(p.positions.size() == c.positions.size() / 3);
      for (size_t v = 0; v < p.positions.size(); ++v) {
        CHECK(p.positions[v] == glm::vec3(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]));
        CHECK(glm::dot(p.normals[v], c.normals[v]) > 0.9999f);
      }
      CHECK(p.indices == c.indices);
    }
  }
}

TEST_CASE("EXT_meshopt_compression: the QUATERNION and EXPONENTIAL filters decode what meshopt encoded") {
  // These filters serve animation and instancing data, so they are checked
  // on the model the decoder writes rather than through a mesh.
  const std::vector<float> quats = {0, 0, 0, 1, 0.5f, 0.5f, 0.5f, 0.5f, 0, 0.70710678f, 0, 0.70710678f, -0.6f, 0, 0.8f, 0};
  std::vector<int16_t> quat_encoded(quats.size());
  meshopt_encodeFilterQuat(quat_encoded.data(), 4, 8, 12, quats.data());
  const std::vector<float> values = {1.5f, -1024.25f, 3.0e-4f, 7.0f, 0.0f, -2.0f};
  std::vector<uint32_t> exp_encoded(values.size());
  meshopt_encodeFilterExp(exp_encoded.data(), values.size(), 4, 20, values.data());

  tinygltf::Model model;
  tinygltf::Buffer streams;
  const std::vector<uint8_t> quat_stream = encode_vertices(quat_encoded, 4, 8);
  const std::vector<uint8_t> exp_stream = encode_vertices(exp_encoded, values.size(), 4);
  streams.data = quat_stream;
  streams.data.insert(streams.data.end(), exp_stream.begin(), exp_stream.end());
  model.buffers.push_back(streams);
  model.bufferViews.resize(2);
  std::vector<cr::MeshoptView> views(2);
  views[0] = {0, 0, 0, quat_stream.size(), 8, 4, cr::MeshoptMode::Attributes, cr::MeshoptFilter::Quaternion};
  views[1] = {1, 0, quat_stream.size(), exp_stream.size(), 4, values.size(), cr::MeshoptMode::Attributes,
              cr::MeshoptFilter::Exponential};
  cr::decode_meshopt_buffer_views(cr::GltfContext{model, "filters.gltf"}, model, views);

  REQUIRE(model.buffers.size() == 3);
  CHECK(model.bufferViews[0].buffer == 1);
  CHECK(model.bufferViews[1].buffer == 2);
  std::vector<int16_t> q(quats.size());
  REQUIRE(model.buffers[1].data.size() == q.size() * 2);
  std::memcpy(q.data(), model.buffers[1].data.data(), model.buffers[1].data.size());
  for (size_t i = 0; i < quats.size(); i += 4) {
    // A quaternion and its negation are the same rotation: compare |dot|.
    float dot = 0.0f;
    for (int k = 0; k < 4; ++k) dot += quats[i + k] * (q[i + k] / 32767.0f);
    CHECK(std::abs(dot) > 0.9999f);
  }
  std::vector<float> e(values.size());
  REQUIRE(model.buffers[2].data.size() == e.size() * 4);
  std::memcpy(e.data(), model.buffers[2].data.data(), model.buffers[2].data.size());
  for (size_t i = 0; i < values.size(); ++i) CHECK(e[i] == doctest::Approx(values[i]).epsilon(1e-5));
}

TEST_CASE("EXT_meshopt_compression: streams and layouts the decoder cannot use are rejected") {
  auto rejected = [](MeshoptCube& c, const std::string& name, const std::string& fault) {
    expect_gltf_rejected(c.asset.write(name, false), fault);
  };
  SUBCASE("stream too short or corrupt") {
    MeshoptCube c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteLength"] = 20;
    rejected(c, "meshopt_short.gltf", "bufferView 0 EXT_meshopt_compression: the 20-byte ATTRIBUTES stream does not decode to 24 elements of 12 bytes");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 2)["byteLength"] = 8;
    rejected(c, "meshopt_short_triangles.gltf", "the 8-byte TRIANGLES stream does not decode");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteOffset"] = 1;  // the header byte (0xa0) is not where the stream starts
    rejected(c, "meshopt_corrupt.gltf", "does not decode");
  }
  SUBCASE("strides, counts and lengths") {
    MeshoptCube c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteStride"] = 6;
    c.asset.b.doc["bufferViews"][0].erase("byteStride");
    c.asset.b.doc["bufferViews"][0]["byteLength"] = 24 * 6;
    rejected(c, "meshopt_stride_6.gltf", "bufferViews[0] EXT_meshopt_compression: byteStride 6 must be a multiple of 4 in [4, 256] for mode ATTRIBUTES");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteStride"] = 16;
    rejected(c, "meshopt_stride_mismatch.gltf", "byteStride 16 differs from the bufferView's byteStride 12");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 3)["byteStride"] = 1;
    rejected(c, "meshopt_index_stride.gltf", "byteStride 1 must be 2 or 4 for mode INDICES");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 2)["count"] = 35;
    rejected(c, "meshopt_triangle_count.gltf", "count 35 must be a multiple of 3 for mode TRIANGLES");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["count"] = 23;
    rejected(c, "meshopt_length.gltf", "count 23 times byteStride 12 is 276 bytes but the bufferView's byteLength is 288");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["filter"] = "OCTAHEDRAL";
    rejected(c, "meshopt_oct_stride.gltf", "byteStride 12 must be 4 or 8 for filter OCTAHEDRAL");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 2)["filter"] = "EXPONENTIAL";
    rejected(c, "meshopt_filter_on_indices.gltf", "filter EXPONENTIAL needs mode ATTRIBUTES");
  }
  SUBCASE("fields") {
    MeshoptCube c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["mode"] = "VERTICES";
    rejected(c, "meshopt_mode.gltf", "mode \"VERTICES\" must be ATTRIBUTES, TRIANGLES or INDICES");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0).erase("count");
    rejected(c, "meshopt_no_count.gltf", "bufferViews[0] EXT_meshopt_compression: count is required");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteLength"] = 5000000000LL;
    rejected(c, "meshopt_huge_length.gltf", "byteLength must be a non-negative integer, found 5000000000");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["byteLength"] = 100000;
    rejected(c, "meshopt_past_buffer.gltf", "bufferView 0 EXT_meshopt_compression (byteOffset 0, byteLength 100000) extends past the end of buffer 0");
  }
  SUBCASE("references to the fallback buffer from anything but a compressed view") {
    MeshoptCube c = meshopt_cube();
    c.asset.b.doc["bufferViews"][0].erase("extensions");
    rejected(c, "meshopt_fallback_plain_view.gltf", "bufferViews[0] reads buffer 1, an EXT_meshopt_compression fallback buffer, but is not compressed");
    c = meshopt_cube();
    meshopt_of(c.asset.b, 0)["buffer"] = 1;
    rejected(c, "meshopt_fallback_stream.gltf", "buffer 1 is a fallback buffer, which holds no compressed data");
    c = meshopt_cube();
    c.asset.b.add("images", {{"bufferView", 0}, {"mimeType", "image/png"}});
    rejected(c, "meshopt_fallback_image.gltf", "images[0] reads bufferView 0 of EXT_meshopt_compression fallback buffer 1");
  }
}

// ---------------------------------------------------------------------------
// External buffer files

TEST_CASE("a missing external buffer file is named; a missing fallback buffer file is not needed") {
  GltfBuilder b;
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}});
  b.add("accessors", {{"bufferView", 0}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 3}});
  b.add("bufferViews", {{"buffer", 0}, {"byteLength", 36}});
  b.add("buffers", {{"byteLength", 36}, {"uri", "no%20such%20geometry.bin"}});
  expect_gltf_rejected(b.write("missing_bin.gltf"), "missing file: no such geometry.bin (buffers[0])");

  MeshoptCube c = meshopt_cube();
  const std::string path = c.asset.write("meshopt_fallback_file.gltf", false);
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(path));
  doc["buffers"][1]["uri"] = "no_such_fallback.bin";
  std::ofstream(path) << doc.dump(1);
  CHECK(cr::load_gltf(path).triangle_count() == 24);
}

// Morph targets: the drawn shape is the rest shape plus the weighted deltas
// (mesh weights, overridden per node, or animated), normals renormalised.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <doctest/doctest.h>

#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

const std::vector<glm::vec3> kBase = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
const std::vector<glm::vec3> kDelta0 = {{0, 0, 1}, {0.5f, 0, 0}, {0, 0, -2}};
const std::vector<glm::vec3> kDelta1 = {{1, 1, 0}, {0, 0, 0.25f}, {-0.75f, 0, 0}};
const std::vector<glm::vec3> kNormalDelta0 = {{1, 0, 0}, {0, 1, -1}, {0, 0, 0}};

std::vector<float> flat(const std::vector<glm::vec3>& v) {
  std::vector<float> out;
  for (const glm::vec3& p : v) out.insert(out.end(), {p.x, p.y, p.z});
  return out;
}

// One triangle (NORMAL +Z) with two morph targets: target 0 moves positions
// and normals, target 1 positions only.
GltfBuilder morph_triangle() {
  GltfBuilder b;
  int pos = b.floats(flat(kBase), "VEC3", 3);
  int nrm = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  int d0 = b.floats(flat(kDelta0), "VEC3", 3);
  int n0 = b.floats(flat(kNormalDelta0), "VEC3", 3);
  int d1 = b.floats(flat(kDelta1), "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}},
                                    {"targets", {{{"POSITION", d0}, {"NORMAL", n0}}, {{"POSITION", d1}}}}}}},
                   {"weights", {0.25, 0.5}}});
  return b;
}

// rest + w0 * delta0 + w1 * delta1, in float and in that order (what the
// loader computes, so the comparison can be exact).
std::vector<glm::vec3> weighted(float w0, float w1) {
  std::vector<glm::vec3> out = kBase;
  for (size_t v = 0; v < out.size(); ++v) {
    if (w0 != 0.0f) out[v] += w0 * kDelta0[v];
    if (w1 != 0.0f) out[v] += w1 * kDelta1[v];
  }
  return out;
}

// Float VEC3 accessor `index` of a .gltf whose buffer 0 is an external file
// and whose views are tightly packed.
std::vector<glm::vec3> read_vec3(const std::string& gltf, int index) {
  std::ifstream in(gltf);
  const nlohmann::json doc = nlohmann::json::parse(in);
  const nlohmann::json& a = doc["accessors"][index];
  const nlohmann::json& view = doc["bufferViews"][a["bufferView"].get<int>()];
  std::ifstream bin(std::filesystem::path(gltf).parent_path() / doc["buffers"][0]["uri"].get<std::string>(),
                    std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(bin)), {});
  const size_t offset = view.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
  std::vector<glm::vec3> out(a["count"].get<size_t>());
  std::memcpy(out.data(), bytes.data() + offset, out.size() * sizeof(glm::vec3));
  return out;
}

}  // namespace

TEST_CASE("morph targets: mesh weights, node weights overriding them, renormalised normals") {
  GltfBuilder b = morph_triangle();
  b.add("nodes", {{"mesh", 0}});                                   // mesh weights (0.25, 0.5)
  b.add("nodes", {{"mesh", 0}, {"weights", {1.0, 0.0}}});          // node weights
  b.add("nodes", {{"mesh", 0}, {"weights", {0.0, 0.0}}, {"translation", {5.0, 0.0, 0.0}}});  // the rest shape
  cr::Scene s = cr::load_gltf(b.write("morph_weights.gltf"));
  REQUIRE(s.draws.size() == 3);
  CHECK(s.meshes.size() == 3);  // the rest mesh and one posed copy per morphed node
  CHECK(s.animation == nullptr);  // nothing changes over time

  CHECK(s.primitive(s.draws[0]).positions == weighted(0.25f, 0.5f));
  CHECK(s.primitive(s.draws[1]).positions == weighted(1.0f, 0.0f));
  CHECK(s.draws[2].mesh == 0);
  CHECK(s.primitive(s.draws[2]).positions == kBase);

  // Normals: normalize(rest + w0 * normal delta), unit length.
  const std::vector<glm::vec3>& n = s.primitive(s.draws[0]).normals;
  for (size_t v = 0; v < 3; ++v) {
    const glm::vec3 expected = glm::normalize(glm::vec3(0, 0, 1) + 0.25f * kNormalDelta0[v]);
    CHECK(glm::length(n[v] - expected) < 1e-6f);
  }
  // Bounds are those of the morphed shape.
  const cr::Primitive& p = s.primitive(s.draws[0]);
  for (const glm::vec3& v : p.positions) {
    CHECK(glm::all(glm::greaterThanEqual(v, s.draws[0].world_bounds_min)));
    CHECK(glm::all(glm::lessThanEqual(v, s.draws[0].world_bounds_max)));
  }
  CHECK(s.draws[0].world_bounds_min.z == -0.5f);  // vertex 2: 0.25 * -2
  CHECK(s.bounds_min.z == -2.0f);                  // draw 1's vertex 2: 1 * -2
}

TEST_CASE("animated morph weights pose the weighted shape at the chosen time") {
  GltfBuilder b = morph_triangle();
  b.doc["meshes"][0]["weights"] = {0.0, 0.0};
  b.add("nodes", {{"mesh", 0}});
  int times = b.floats({0, 1, 2}, "SCALAR", 1);
  int values = b.floats({0, 0, 1, 0, 1, 1}, "SCALAR", 1);  // (w0, w1) per key
  b.add("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}},
                       {"samplers", {{{"input", times}, {"output", values}}}}});
  cr::Scene s = cr::load_gltf(b.write("morph_animated.gltf"));
  REQUIRE(s.animation != nullptr);
  REQUIRE(s.draws.size() == 1);
  CHECK(s.primitive(s.draws[0]).positions == kBase);  // rest weights are zero
  cr::pose_scene(s, *s.animation, 0, 0.5);
  CHECK(s.primitive(s.draws[0]).positions == weighted(0.5f, 0.0f));
  cr::pose_scene(s, *s.animation, 0, 1.5);
  CHECK(s.primitive(s.draws[0]).positions == weighted(1.0f, 0.5f));
  cr::pose_scene(s, *s.animation, std::nullopt, 0.0);
  CHECK(s.primitive(s.draws[0]).positions == kBase);
}

TEST_CASE("MorphPrimitivesTest draws base + 0.5 * delta (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.draws.size() == 2);
  // Accessors (POSITION, target POSITION) of primitives 0 and 1; mesh weight 0.5.
  const int accessors[2][2] = {{2, 4}, {7, 9}};
  for (int prim = 0; prim < 2; ++prim) {
    CAPTURE(prim);
    const std::vector<glm::vec3> base = read_vec3(path, accessors[prim][0]);
    const std::vector<glm::vec3> delta = read_vec3(path, accessors[prim][1]);
    const cr::Primitive& drawn = s.primitive(s.draws[prim]);
    REQUIRE(drawn.positions.size() == base.size());
    for (size_t v = 0; v < base.size(); ++v) CHECK(drawn.positions[v] == base[v] + 0.5f * delta[v]);
    CHECK(s.meshes[0].primitives[prim].positions == base);  // the rest shape is kept
    CHECK(drawn.bounds_max.y == doctest::Approx(0.1));      // the raised vertices
  }
}

TEST_CASE("malformed morph targets and weights are rejected") {
  {
    GltfBuilder b = morph_triangle();
    b.doc["meshes"][0]["weights"] = {0.5};
    b.add("nodes", {{"mesh", 0}});
    expect_gltf_rejected(b.write("morph_mesh_weights_count.gltf"), "mesh 0 weights has 1 values but its mesh has 2 morph targets");
  }
  {
    GltfBuilder b = morph_triangle();
    b.add("nodes", {{"mesh", 0}, {"weights", {0.5, 0.5, 0.5}}});
    expect_gltf_rejected(b.write("morph_node_weights_count.gltf"), "node 0 weights has 3 values but its mesh has 2 morph targets");
  }
  {
    GltfBuilder b = morph_triangle();
    nlohmann::json second = b.doc["meshes"][0]["primitives"][0];
    second["targets"].erase(1);
    b.doc["meshes"][0]["primitives"].push_back(second);
    b.add("nodes", {{"mesh", 0}});
    expect_gltf_rejected(b.write("morph_target_counts.gltf"), "primitive 1 has 1 morph targets but primitive 0 has 2");
  }
  {
    GltfBuilder b = morph_triangle();
    b.doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = b.floats({0, 0, 0, 0, NAN, 0, 0, 0, 0}, "VEC3", 3);
    b.add("nodes", {{"mesh", 0}});
    expect_gltf_rejected(b.write("morph_nan_delta.gltf"), "target 1 POSITION: vertex 1 is not finite");
  }
  {
    GltfBuilder b = morph_triangle();
    b.doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = b.floats({0, 0, 0, 0, 0, 0}, "VEC3", 3);
    b.add("nodes", {{"mesh", 0}});
    expect_gltf_rejected(b.write("morph_delta_count.gltf"), "target 1 POSITION has 2 elements but POSITION has 3");
  }
  {
    GltfBuilder b = morph_triangle();
    b.add("nodes", {{"weights", {0.5, 0.5}}});
    expect_gltf_rejected(b.write("morph_weights_no_mesh.gltf"), "node 0 has morph weights but no mesh");
  }
}

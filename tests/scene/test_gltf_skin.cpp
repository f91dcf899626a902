// Skins: linear blend skinning on the CPU at load (and at any pose), normals
// by the inverse-transpose; malformed skins and influences are rejected.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

// A JOINTS_n accessor: UNSIGNED_BYTE VEC4.
int joints_accessor(GltfBuilder& b, const std::vector<uint8_t>& joints) {
  const int a = b.indices(joints);
  b.doc["accessors"][a]["type"] = "VEC4";
  b.doc["accessors"][a]["count"] = joints.size() / 4;
  return a;
}

std::vector<float> floats(const glm::mat4& m) { return {glm::value_ptr(m), glm::value_ptr(m) + 16}; }

const glm::quat kTurn = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));

// Node 0 draws a triangle skinned by joints A (node 1, at (0, 1, 0)) and B
// (node 2, child of A at (0, 1, 0), turned 90 degrees about +Z and scaled
// (2, 1, 1)). The bind pose has both joints unrotated and unscaled.
// Vertex 0 follows A, vertex 1 follows B, vertex 2 is 1/4 A and 3/4 B.
GltfBuilder two_joint_skin() {
  GltfBuilder b;
  int pos = b.floats({1, 0, 0, 1, 2, 0, 2, 2, 0}, "VEC3", 3);
  int nrm = b.floats({0, 0, 1, 1, 1, 0, 0, 0, 1}, "VEC3", 3);
  int joints = joints_accessor(b, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
  int weights = b.floats({1, 0, 0, 0, 1, 0, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4", 4);
  std::vector<float> ibm = floats(glm::translate(glm::mat4(1.0f), glm::vec3(0, -1, 0)));
  const std::vector<float> ibm_b = floats(glm::translate(glm::mat4(1.0f), glm::vec3(0, -2, 0)));
  ibm.insert(ibm.end(), ibm_b.begin(), ibm_b.end());
  int inverse_bind = b.floats(ibm, "MAT4", 16);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}}}}});
  // The skinned node's own transform must be ignored (glTF 2.0).
  b.add("nodes", {{"mesh", 0}, {"skin", 0}, {"translation", {100.0, 0.0, 0.0}}});
  b.add("nodes", {{"translation", {0.0, 1.0, 0.0}}, {"children", {2}}});
  b.add("nodes", {{"translation", {0.0, 1.0, 0.0}}, {"rotation", {kTurn.x, kTurn.y, kTurn.z, kTurn.w}}, {"scale", {2.0, 1.0, 1.0}}});
  b.add("skins", {{"joints", {1, 2}}, {"inverseBindMatrices", inverse_bind}, {"skeleton", 1}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0, 1}}}});
  return b;
}

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) { return glm::length(a - b) < eps; }

}  // namespace

TEST_CASE("a two-joint skin gives the closed-form vertex positions and inverse-transpose normals") {
  cr::Scene s = cr::load_gltf(two_joint_skin().write("two_joint_skin.gltf"));
  REQUIRE(s.draws.size() == 1);
  const cr::Draw& d = s.draws[0];
  CHECK(d.world == glm::mat4(1.0f));  // skinned vertices are in world space
  const cr::Primitive& p = s.primitive(d);
  // A is at its bind pose: vertex 0 stays. B = T(0,2,0) * Rz(90) * S(2,1,1) * T(0,-2,0).
  CHECK(near(p.positions[0], {1, 0, 0}));
  CHECK(near(p.positions[1], {0, 4, 0}));                    // (1,0,0) -> (2,0,0) -> (0,2,0) -> (0,4,0)
  CHECK(near(p.positions[2], 0.25f * glm::vec3(2, 2, 0) + 0.75f * glm::vec3(0, 6, 0)));
  CHECK(near(p.normals[0], {0, 0, 1}));
  // (R S)^-T n = R S^-1 n: (1,1,0) -> (0.5,1,0) -> (-1,0.5,0).
  CHECK(near(p.normals[1], glm::normalize(glm::vec3(-1, 0.5f, 0))));
  const glm::mat4 b = glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)) * glm::mat4_cast(kTurn) *
                      glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1)) * glm::translate(glm::mat4(1.0f), glm::vec3(0, -2, 0));
  const glm::mat3 blend = 0.25f * glm::mat3(1.0f) + 0.75f * glm::mat3(b);
  CHECK(near(p.normals[2], glm::normalize(glm::inverseTranspose(blend) * glm::vec3(0, 0, 1))));
  // Bounds are the posed ones, in world space.
  CHECK(near(d.world_bounds_min, {0, 0, 0}));
  CHECK(near(d.world_bounds_max, {1, 5, 0}));
  CHECK(s.meshes[0].primitives[0].positions[1] == glm::vec3(1, 2, 0));  // the rest shape is kept
}

TEST_CASE("an animated joint re-poses the skin") {
  GltfBuilder b = two_joint_skin();
  int times = b.floats({0, 1}, "SCALAR", 1);
  int rotations = b.floats({kTurn.x, kTurn.y, kTurn.z, kTurn.w, 0, 0, 0, 1}, "VEC4", 4);
  b.add("animations", {{"name", "unturn"},
                       {"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}}}},
                       {"samplers", {{{"input", times}, {"output", rotations}}}}});
  cr::Scene s = cr::load_gltf(b.write("two_joint_skin_animated.gltf"));
  REQUIRE(s.animation != nullptr);
  cr::pose_scene(s, *s.animation, 0, 1.0);
  const cr::Primitive& p = s.primitive(s.draws.at(0));
  CHECK(near(p.positions[1], {2, 2, 0}));  // B unturned: (1,0,0) -> (2,0,0) -> (2,2,0)
  cr::pose_scene(s, *s.animation, 0, 0.5);  // halfway: turned 45 degrees
  CHECK(near(s.primitive(s.draws.at(0)).positions[1], {std::sqrt(2.0f), 2.0f + std::sqrt(2.0f), 0}));
  cr::pose_scene(s, *s.animation, std::nullopt, 0.0);
  CHECK(near(s.primitive(s.draws.at(0)).positions[1], {0, 4, 0}));
}

TEST_CASE("Fox at rest and walking: different, finite, plausible bounds (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/Fox/glTF/Fox.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.animation != nullptr);
  REQUIRE(s.animation->animations.size() == 3);
  CHECK(s.animation->animations[0].name == "Survey");
  CHECK(s.animation->animations[1].name == "Walk");
  CHECK(s.animation->animations[2].name == "Run");
  REQUIRE(s.draws.size() == 1);
  const std::vector<glm::vec3> rest = s.primitive(s.draws[0]).positions;
  const glm::vec3 rest_min = s.bounds_min, rest_max = s.bounds_max;
  // At rest the skin reproduces the bind shape (the rest pose is the bind pose).
  const cr::Primitive& file_shape = s.meshes[0].primitives[0];
  float worst = 0.0f;
  for (size_t v = 0; v < rest.size(); ++v) worst = std::max(worst, glm::length(rest[v] - file_shape.positions[v]));
  CHECK(worst < 1e-3f);

  cr::pose_scene(s, *s.animation, 1, 0.3);
  const cr::Primitive& walk = s.primitive(s.draws[0]);
  REQUIRE(walk.positions.size() == rest.size());
  float moved = 0.0f;
  for (size_t v = 0; v < rest.size(); ++v) {
    const glm::vec3& p = walk.positions[v];
    REQUIRE((std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)));
    CHECK(std::abs(glm::length(walk.normals[v]) - 1.0f) < 1e-4f);
    CHECK(glm::all(glm::greaterThanEqual(p, s.bounds_min)));
    CHECK(glm::all(glm::lessThanEqual(p, s.bounds_max)));
    moved = std::max(moved, glm::length(p - rest[v]));
  }
  CHECK(moved > 1.0f);  // legs swing by centimetres-sized units (the fox is ~150 units long)
  const glm::vec3 rest_size = rest_max - rest_min, walk_size = s.bounds_max - s.bounds_min;
  for (int c = 0; c < 3; ++c) {
    CAPTURE(c);
    CHECK(walk_size[c] > 0.5f * rest_size[c]);
    CHECK(walk_size[c] < 2.0f * rest_size[c]);
  }
  CHECK(std::max({rest_size.x, rest_size.y, rest_size.z}) > 100.0f);
  CHECK(std::max({rest_size.x, rest_size.y, rest_size.z}) < 300.0f);
}

TEST_CASE("malformed skins and skin influences are rejected") {
  {
    GltfBuilder b = two_joint_skin();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = joints_accessor(b, {0, 0, 0, 0, 5, 0, 0, 0, 0, 1, 0, 0});
    expect_gltf_rejected(b.write("skin_joint_out_of_range.gltf"), "uses joint 5 but its skin 0 has 2 joints");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
        b.floats({1, 0, 0, 0, 0.5f, 0.2f, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4", 4);
    expect_gltf_rejected(b.write("skin_weights_sum.gltf"), "skin weights of vertex 1 sum to 0.7");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
        b.floats({1, 0, 0, 0, 1.5f, -0.5f, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4", 4);
    expect_gltf_rejected(b.write("skin_negative_weight.gltf"), "vertex 1 has a negative or non-finite weight");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    expect_gltf_rejected(b.write("skin_no_weights.gltf"), "has JOINTS_0 but no WEIGHTS_0");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["skins"][0]["inverseBindMatrices"] = b.floats(floats(glm::mat4(1.0f)), "MAT4", 16);
    expect_gltf_rejected(b.write("skin_few_matrices.gltf"), "inverseBindMatrices has 1 matrices for 2 joints");
  }
  {
    GltfBuilder b = two_joint_skin();
    std::vector<float> m = floats(glm::mat4(1.0f));
    m[5] = NAN;
    m.insert(m.end(), m.begin(), m.end());
    b.doc["skins"][0]["inverseBindMatrices"] = b.floats(m, "MAT4", 16);
    expect_gltf_rejected(b.write("skin_nan_matrix.gltf"), "inverseBindMatrices: matrix 0 is not finite");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["skins"][0]["joints"] = {1, 9};
    expect_gltf_rejected(b.write("skin_joint_node_out_of_range.gltf"), "skin 0 joint 9 out of range (3 nodes)");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["skins"][0]["joints"] = {1, 1};
    expect_gltf_rejected(b.write("skin_joint_twice.gltf"), "skin 0 lists node 1 twice as a joint");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["nodes"][1]["skin"] = 0;
    expect_gltf_rejected(b.write("skin_without_mesh.gltf"), "node 1 has a skin but no mesh");
  }
  {
    GltfBuilder b = two_joint_skin();
    b.doc["nodes"][0]["skin"] = 3;
    expect_gltf_rejected(b.write("skin_out_of_range.gltf"), "node 0 skin 3 out of range (1 skins)");
  }
}

TEST_CASE("a skin on a mesh without JOINTS_0 draws it unskinned, placed by its node") {
  GltfBuilder b = two_joint_skin();
  b.doc["meshes"][0]["primitives"][0]["attributes"].erase("JOINTS_0");
  b.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  cr::Scene s = cr::load_gltf(b.write("skin_no_joints.gltf"));
  REQUIRE(s.draws.size() == 1);
  CHECK(s.draws[0].world == glm::translate(glm::mat4(1.0f), glm::vec3(100, 0, 0)));
  CHECK(s.primitive(s.draws[0]).positions[1] == glm::vec3(1, 2, 0));
}

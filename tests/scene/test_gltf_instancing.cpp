// EXT_mesh_gpu_instancing: one draw per instance and primitive, placed by
// node world * instance TRS; malformed instance attributes are rejected.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <tuple>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/gltf_loader.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

bool mat_close(const glm::mat4& a, const glm::mat4& b, float eps = 1e-5f) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(a[c][r] - b[c][r]) > eps) return false;
  return true;
}

// A one-triangle mesh drawn by node 1, child of node 0 (translated by
// (0, 10, 0)), with `instancing` as node 1's EXT_mesh_gpu_instancing.
GltfBuilder instanced_scene(nlohmann::json instancing) {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.add("nodes", {{"translation", {0.0, 10.0, 0.0}}, {"children", {1}}});
  b.add("nodes", {{"mesh", 0}, {"scale", {2.0, 2.0, 2.0}}, {"extensions", {{"EXT_mesh_gpu_instancing", instancing}}}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  return b;
}

}  // namespace

TEST_CASE("instances are placed by node world * translation * rotation * scale") {
  GltfBuilder b = instanced_scene({});
  const glm::quat q = glm::angleAxis(0.8f, glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f)));
  int t = b.floats({1, 0, 0, 0, 2, 0, 0, 0, 3}, "VEC3", 3);
  int r = b.floats({0, 0, 0, 1, q.x, q.y, q.z, q.w, 0, 0, 0, 1}, "VEC4", 4);
  int s = b.floats({1, 1, 1, 1, 1, 1, 0.5f, 2, 3}, "VEC3", 3);
  int id = b.floats({7, 8, 9}, "SCALAR", 1);
  b.doc["nodes"][1]["extensions"]["EXT_mesh_gpu_instancing"] = {
      {"attributes", {{"TRANSLATION", t}, {"ROTATION", r}, {"SCALE", s}, {"_ID", id}}}};
  cr::Scene scene = cr::load_gltf(b.write("instances_trs.gltf"));
  REQUIRE(scene.draws.size() == 3);  // the mesh itself is not drawn besides its instances
  const glm::mat4 node = glm::translate(glm::mat4(1.0f), glm::vec3(0, 10, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
  const glm::mat4 expected[3] = {
      node * glm::translate(glm::mat4(1.0f), glm::vec3(1, 0, 0)),
      node * glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)) * glm::mat4_cast(q),
      node * glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 3)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 2, 3)),
  };
  for (int i = 0; i < 3; ++i) {
    CAPTURE(i);
    CHECK(mat_close(scene.draws[i].world, expected[i], 1e-5f));
    // World bounds hold the instance's vertices.
    for (const glm::vec3& p : scene.primitive(scene.draws[i]).positions) {
      const glm::vec3 w(expected[i] * glm::vec4(p, 1.0f));
      CHECK(glm::all(glm::greaterThanEqual(w, scene.draws[i].world_bounds_min - 1e-4f)));
      CHECK(glm::all(glm::lessThanEqual(w, scene.draws[i].world_bounds_max + 1e-4f)));
    }
  }
  CHECK(scene.bounds_max.z >= 3.0f * 2.0f - 1e-4f);  // instance 2 reaches z = node scale * 3
}

TEST_CASE("SimpleInstancing draws its 125 cubes at 125 grid positions (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/SimpleInstancing/glTF/SimpleInstancing.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.draws.size() == 125);
  CHECK(s.triangle_count() == 125 * 12);
  std::set<std::tuple<float, float, float>> origins;
  for (const cr::Draw& d : s.draws) {
    const glm::vec3 o(d.world[3]);
    origins.insert({o.x, o.y, o.z});
    for (int c = 0; c < 3; ++c) {
      // A 5 x 5 x 5 grid with 2.5 m spacing.
      CHECK(std::abs(o[c] / 2.5f - std::round(o[c] / 2.5f)) < 1e-5f);
      CHECK(o[c] >= 0.0f);
      CHECK(o[c] <= 10.0f);
    }
  }
  CHECK(origins.size() == 125);
  // Instance 4: at (0, 0, 10), turned 90 degrees about +Z, scaled (1, 1, 2).
  const glm::mat4 expected = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 10)) *
                             glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)) *
                             glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, 2));
  CHECK(mat_close(s.draws[4].world, expected, 1e-5f));
  for (const cr::Draw& d : s.draws) {
    CHECK(glm::all(glm::greaterThanEqual(d.world_bounds_min, s.bounds_min)));
    CHECK(glm::all(glm::lessThanEqual(d.world_bounds_max, s.bounds_max)));
  }
  CHECK(s.bounds_max.x > 10.0f);  // the far cubes reach past their origins
}

TEST_CASE("malformed EXT_mesh_gpu_instancing attributes are rejected") {
  auto write = [](const std::string& name, auto add_attributes) {
    GltfBuilder b = instanced_scene({});
    b.doc["nodes"][1]["extensions"]["EXT_mesh_gpu_instancing"] = {{"attributes", add_attributes(b)}};
    return b.write(name);
  };
  expect_gltf_rejected(write("instances_count_mismatch.gltf", [](GltfBuilder& b) {
                         return nlohmann::json{{"TRANSLATION", b.floats({0, 0, 0, 1, 1, 1}, "VEC3", 3)},
                                               {"SCALE", b.floats({1, 1, 1}, "VEC3", 3)}};
                       }),
                       "attribute TRANSLATION has 2 elements but SCALE has 1");
  expect_gltf_rejected(write("instances_nan.gltf", [](GltfBuilder& b) {
                         return nlohmann::json{{"TRANSLATION", b.floats({0, 0, 0, 1, NAN, 1}, "VEC3", 3)}};
                       }),
                       "instance 1 TRANSLATION is not finite");
  expect_gltf_rejected(write("instances_zero_rotation.gltf", [](GltfBuilder& b) {
                         return nlohmann::json{{"ROTATION", b.floats({0, 0, 0, 0}, "VEC4", 4)}};
                       }),
                       "instance 0 ROTATION is not a finite non-zero quaternion");
  expect_gltf_rejected(write("instances_rotation_vec3.gltf", [](GltfBuilder& b) {
                         return nlohmann::json{{"ROTATION", b.floats({0, 0, 1}, "VEC3", 3)}};
                       }),
                       "expected VEC4");
  expect_gltf_rejected(write("instances_unknown.gltf", [](GltfBuilder& b) {
                         return nlohmann::json{{"POSITION", b.floats({0, 0, 1}, "VEC3", 3)}};
                       }),
                       "attribute POSITION is not TRANSLATION, ROTATION, SCALE");
  expect_gltf_rejected(write("instances_empty.gltf", [](GltfBuilder&) { return nlohmann::json::object(); }),
                       "EXT_mesh_gpu_instancing must have a non-empty object \"attributes\"");
  expect_gltf_rejected(write("instances_not_index.gltf", [](GltfBuilder&) { return nlohmann::json{{"SCALE", "zero"}}; }),
                       "attribute SCALE must be an accessor index");
}

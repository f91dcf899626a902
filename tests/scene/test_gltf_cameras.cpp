// glTF cameras: perspective and orthographic ones listed in traversal order
// with their projections; invalid projections are rejected.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>

#include "engine/scene/gltf_loader.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

std::string camera_file(const std::string& name, nlohmann::json camera) {
  GltfBuilder b;
  b.add("cameras", std::move(camera));
  b.add("nodes", {{"camera", 0}, {"translation", {1.0, 2.0, 3.0}}});
  return b.write(name);
}

}  // namespace

TEST_CASE("orthographic cameras keep their magnifications and clip planes, in traversal order") {
  GltfBuilder b;
  b.add("cameras", {{"type", "orthographic"}, {"orthographic", {{"xmag", 4.0}, {"ymag", 2.5}, {"znear", 0.0}, {"zfar", 50.0}}}});
  b.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.2}, {"zfar", 30.0}}}});
  b.add("cameras", {{"type", "orthographic"}, {"orthographic", {{"xmag", -3.0}, {"ymag", 1.0}, {"znear", 1.0}, {"zfar", 2.0}}}});
  // Node 0 (camera 1) has child node 1 (camera 0); node 2 has camera 2.
  b.add("nodes", {{"camera", 1}, {"children", {1}}});
  b.add("nodes", {{"camera", 0}, {"translation", {0.0, 0.0, 5.0}}});
  b.add("nodes", {{"camera", 2}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0, 2}}}});
  cr::Scene s = cr::load_gltf(b.write("orthographic.gltf"));
  REQUIRE(s.cameras.size() == 3);
  CHECK_FALSE(s.cameras[0].orthographic);
  CHECK(s.cameras[0].yfov_rad == doctest::Approx(0.9));
  const cr::GltfCamera& o = s.cameras[1];
  CHECK(o.orthographic);
  CHECK(o.xmag == 4.0f);
  CHECK(o.ymag == 2.5f);
  CHECK(o.znear == 0.0f);
  CHECK(o.zfar == 50.0f);
  CHECK(o.position == glm::vec3(0, 0, 5));
  CHECK(o.forward == glm::vec3(0, 0, -1));
  // A negative magnification (the spec advises against it) keeps its size, with a warning.
  CHECK(s.cameras[2].xmag == 3.0f);
  CHECK(s.cameras[2].znear == 1.0f);
  CHECK(s.cameras[2].zfar == 2.0f);
}

TEST_CASE("Khronos Cameras: a perspective and an orthographic camera (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/Cameras/glTF/Cameras.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.cameras.size() == 2);
  const cr::GltfCamera& p = s.cameras[0];
  CHECK_FALSE(p.orthographic);
  CHECK(p.yfov_rad == doctest::Approx(0.7));
  CHECK(p.znear == doctest::Approx(0.01));
  CHECK(p.aspect.value_or(0.0f) == 1.0f);
  const cr::GltfCamera& o = s.cameras[1];
  CHECK(o.orthographic);
  CHECK(o.xmag == 1.0f);
  CHECK(o.ymag == 1.0f);
  CHECK(o.znear == doctest::Approx(0.01));
  CHECK(o.zfar == 100.0f);
  for (const cr::GltfCamera& c : s.cameras) {
    CHECK(c.position == glm::vec3(0.5f, 0.5f, 3.0f));
    CHECK(c.forward == glm::vec3(0, 0, -1));
    CHECK(c.up == glm::vec3(0, 1, 0));
  }
}

TEST_CASE("invalid camera projections are rejected") {
  auto ortho = [](double xmag, double ymag, double znear, double zfar) {
    return nlohmann::json{{"type", "orthographic"},
                          {"orthographic", {{"xmag", xmag}, {"ymag", ymag}, {"znear", znear}, {"zfar", zfar}}}};
  };
  expect_gltf_rejected(camera_file("ortho_zero_xmag.gltf", ortho(0, 1, 0.1, 10)), "camera 0 xmag and ymag must be finite and non-zero");
  expect_gltf_rejected(camera_file("ortho_zero_ymag.gltf", ortho(1, 0, 0.1, 10)), "camera 0 xmag and ymag must be finite and non-zero");
  expect_gltf_rejected(camera_file("ortho_far_before_near.gltf", ortho(1, 1, 5, 5)), "zfar must be finite and greater than znear");
  expect_gltf_rejected(camera_file("ortho_negative_near.gltf", ortho(1, 1, -1, 5)), "znear must be finite and >= 0");
  expect_gltf_rejected(camera_file("ortho_missing_ymag.gltf",
                                   {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"znear", 0}, {"zfar", 1}}}}),
                       "'cameras[0].orthographic.ymag' is required");
  {
    GltfBuilder b;
    b.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}});
    b.add("nodes", {{"camera", 0}, {"scale", {1.0, 1.0, 0.0}}});
    expect_gltf_rejected(b.write("camera_flat_node.gltf"), "node 0 places a camera with a degenerate transform");
  }
  expect_gltf_rejected(camera_file("perspective_far_before_near.gltf",
                                   {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 2.0}, {"zfar", 1.0}}}}),
                       "zfar must be finite and greater than znear");
}

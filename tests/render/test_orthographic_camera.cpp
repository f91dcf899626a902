// Orthographic views: the projection's closed form, and the Khronos Cameras
// model seen through its orthographic camera (a square plane tilted away
// from the camera keeps parallel, vertical sides: a rectangle of the width
// xmag/ymag says) and through its perspective one (the far edge shrinks).
#include <doctest/doctest.h>

#include <cmath>

#include "engine/render/frame_view.h"
#include "engine/render/renderer.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf_loader.h"
#include "tests/khronos_assets.h"

TEST_CASE("orthographic projection: x, y scale by the half extents; depth znear -> 1, zfar -> 0") {
  cr::Camera cam = cr::Camera::look_at({0, 0, 0}, {0, 0, -1}, 1.0f, 2.0f, 0.5f);
  cam.orthographic = true;
  cam.ortho_half_height = 3.0f;
  cam.zfar = 10.5f;
  const glm::mat4 vp = cam.view_proj();
  const glm::vec4 near_corner = vp * glm::vec4(6.0f, 3.0f, -0.5f, 1.0f);
  CHECK(near_corner.w == doctest::Approx(1.0f));
  CHECK(near_corner.x == doctest::Approx(1.0f));
  CHECK(near_corner.y == doctest::Approx(1.0f));
  CHECK(near_corner.z == doctest::Approx(1.0f));
  const glm::vec4 far_centre = vp * glm::vec4(0.0f, 0.0f, -10.5f, 1.0f);
  CHECK(far_centre.z == doctest::Approx(0.0f).epsilon(1e-6));
  // view_depth inverts the depth mapping.
  const glm::vec4 mid = vp * glm::vec4(1.0f, -2.0f, -4.0f, 1.0f);
  CHECK(cam.view_depth(mid.z / mid.w) == doctest::Approx(4.0f));
  // Every pixel looks along forward.
  const glm::vec3 d = cam.ray_direction(0.5f, 0.5f, 64, 32);
  CHECK(glm::dot(d, cam.forward) == doctest::Approx(1.0f));
}

namespace {

// Leftmost and rightmost covered column of row y.
std::pair<int, int> covered_span(const cr::FrameBuffers& b, int y) {
  int lo = b.width, hi = -1;
  for (int x = 0; x < b.width; ++x)
    if (b.depth[b.index(x, y)] > 0.0f) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  return {lo, hi};
}

}  // namespace

TEST_CASE("Cameras: the orthographic camera shows the tilted square as a rectangle, the perspective one as a trapezoid") {
  const auto gltf = cr::test::asset_path("khronos/Cameras/glTF/Cameras.gltf");
  if (!gltf) return;
  const cr::Scene scene = cr::load_gltf(*gltf);
  REQUIRE(scene.cameras.size() == 2);
  REQUIRE_FALSE(scene.cameras[0].orthographic);
  REQUIRE(scene.cameras[1].orthographic);
  cr::Profile profile = cr::load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  profile.width = 320;
  profile.height = 240;
  cr::JobSystem jobs(2);
  auto spans = [&](int camera) {
    cr::SceneDescription d = cr::load_scene_description(*gltf, {});
    d.camera.gltf_camera = camera;
    CHECK(cr::orthographic_view(scene, d) == (camera == 1));
    cr::Renderer r(scene, d, profile, {}, jobs);
    r.render_frame(0);
    const cr::FrameBuffers& b = r.buffers();
    int top = -1, bottom = -1;
    for (int y = 0; y < b.height; ++y)
      if (covered_span(b, y).second >= 0) {
        if (top < 0) top = y;
        bottom = y;
      }
    REQUIRE(top >= 0);
    return std::make_pair(covered_span(b, top + 1), covered_span(b, bottom - 1));
  };
  const auto [ortho_far, ortho_near] = spans(1);
  // The unit square is 1 m wide; the view is 2 * ymag * aspect = 8/3 m wide: 120 of 320 pixels.
  CHECK(std::abs((ortho_far.second - ortho_far.first + 1) - 120) <= 1);
  CHECK(std::abs((ortho_near.second - ortho_near.first + 1) - 120) <= 1);
  CHECK(std::abs(ortho_far.first - ortho_near.first) <= 1);
  const auto [persp_far, persp_near] = spans(0);
  CHECK((persp_far.second - persp_far.first) < (persp_near.second - persp_near.first) - 4);
}

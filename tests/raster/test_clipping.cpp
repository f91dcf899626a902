// Near-plane and guard-band clipping against analytic ray casting.
#include <doctest/doctest.h>

#include <cmath>

#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kClipW = 160, kClipH = 120;

struct CoverageCheck {
  int expected_covered = 0;
  int wrong = 0;
  int bad_depth = 0;
};

// Renders one world triangle and compares each sample with a ray cast:
// covered iff the ray hits the triangle in front of the near plane, and then
// the stored depth is znear / view depth. Samples within a small margin of
// the triangle's edges or of the near plane are not judged.
CoverageCheck render_and_compare(const Camera& cam, const glm::vec3 (&v)[3], RasterStats* stats_out = nullptr) {
  const Primitive p = test::make_primitive({v[0], v[1], v[2]}, {0, 1, 2});
  const RasterDraw draw = test::draw_of(p, test::world_to_clip(cam), 0);
  JobSystem jobs(2);
  TiledRasterizer r;
  const RasterStats& stats = r.render_visibility(jobs, kClipW, kClipH, 16, {&draw, 1});
  if (stats_out) *stats_out = stats;
  CoverageCheck out;
  for (int y = 0; y < kClipH; ++y)
    for (int x = 0; x < kClipW; ++x) {
      const glm::dvec3 d(cam.ray_direction(x + 0.5f, y + 0.5f, kClipW, kClipH));
      const auto hit = test::intersect_plane(cam.position, d, v[0], v[1], v[2]);
      bool expected = false;
      double depth = 0.0;
      if (hit && hit->t > 0.0) {
        const double margin = std::min({hit->b.x, hit->b.y, hit->b.z});
        depth = hit->t * glm::dot(d, glm::dvec3(cam.forward));
        if (std::abs(margin) < 1e-3 || std::abs(depth - cam.znear) < 1e-4) continue;
        expected = margin > 0.0 && depth > cam.znear;
      }
      const size_t i = r.visibility().index(x, y);
      const bool covered = r.visibility().triangle[i] != kNoTriangle;
      out.expected_covered += expected;
      out.wrong += covered != expected;
      if (covered && expected && std::abs(r.visibility().depth[i] - cam.znear / depth) > 1e-6 + 1e-5 * (cam.znear / depth))
        ++out.bad_depth;
    }
  return out;
}

const Camera kCamera = Camera::look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 1.2f, float(kClipW) / kClipH, 0.1f);

TEST_CASE("triangle crossing the near plane covers exactly its part in front") {
  // Lies almost in the view direction: starts 5 cm in front of the camera
  // (inside the near plane), reaches 6 m away.
  const glm::vec3 v[3] = {{-0.02f, -0.02f, -0.05f}, {4.0f, -0.9f, -6.0f}, {-4.0f, 0.8f, -6.0f}};
  RasterStats stats;
  const CoverageCheck c = render_and_compare(kCamera, v, &stats);
  CHECK(stats.triangles_clipped == 1);
  CHECK(c.expected_covered > 1000);
  CHECK(c.wrong == 0);
  CHECK(c.bad_depth == 0);
}

TEST_CASE("vertices behind the camera are not projected through the eye") {
  // Two vertices behind the camera: a naive divide by w would mirror them
  // onto the screen. Only the part in front may appear.
  const glm::vec3 v[3] = {{0.4f, -0.3f, -4.0f}, {-3.0f, 2.0f, 3.0f}, {3.0f, 2.5f, 2.0f}};
  RasterStats stats;
  const CoverageCheck c = render_and_compare(kCamera, v, &stats);
  CHECK(stats.triangles_clipped == 1);
  CHECK(c.expected_covered > 100);
  CHECK(c.wrong == 0);
  CHECK(c.bad_depth == 0);
}

TEST_CASE("huge triangle is clipped to the guard band and still covers the right samples") {
  const glm::vec3 v[3] = {{-5000.0f, -3.0f, -2.0f}, {5000.0f, -3.0f, -2.0f}, {0.0f, 4000.0f, -30.0f}};
  RasterStats stats;
  const CoverageCheck c = render_and_compare(kCamera, v, &stats);
  CHECK(stats.triangles_clipped == 1);
  CHECK(c.expected_covered > 1000);
  CHECK(c.wrong == 0);
  CHECK(c.bad_depth == 0);
}

TEST_CASE("triangle entirely behind the camera or the near plane is dropped") {
  for (float z : {2.0f, -0.05f}) {
    CAPTURE(z);
    const glm::vec3 v[3] = {{-1.0f, -1.0f, z}, {1.0f, -1.0f, z}, {0.0f, 1.0f, z}};
    RasterStats stats;
    const CoverageCheck c = render_and_compare(kCamera, v, &stats);
    CHECK(stats.triangles_in == 1);
    CHECK(stats.triangles_culled == 1);
    CHECK(stats.screen_triangles == 0);
    CHECK(stats.pixels_covered == 0);
    CHECK(c.expected_covered == 0);
    CHECK(c.wrong == 0);
  }
}

}  // namespace
}  // namespace cr

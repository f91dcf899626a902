// Perspective-correct barycentrics and their analytic screen derivatives.
#include <doctest/doctest.h>

#include <cmath>

#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kInterpW = 200, kInterpH = 150;

// Analytic barycentrics of the ray through screen position (px, py) with the
// plane of triangle v (extended beyond its edges).
glm::dvec3 analytic(const Camera& cam, const glm::vec3* v, double px, double py) {
  // Camera::ray_direction in double, so finite differences are not float noise.
  const double t = std::tan(0.5 * double(cam.vfov_rad));
  const double sx = (2.0 * px / kInterpW - 1.0) * t * double(cam.aspect), sy = (1.0 - 2.0 * py / kInterpH) * t;
  const glm::dvec3 d = glm::dvec3(cam.forward) + sx * glm::dvec3(cam.right) + sy * glm::dvec3(cam.up);
  return test::intersect_plane(cam.position, d, v[0], v[1], v[2])->b;
}

TEST_CASE("barycentrics of a steep quad match ray-plane intersection; derivatives match finite differences") {
  // A 1 x 40 m strip of floor 1 m below the camera, seen at a grazing angle,
  // so w varies by ~40x across it.
  const Camera cam = Camera::look_at({0.0, 1.0, 0.0}, {0.0, 0.6, -10.0}, 1.0f, float(kInterpW) / kInterpH, 0.1f);
  const std::vector<glm::vec3> pos{{-1.0f, 0.0f, -0.5f}, {1.0f, 0.0f, -0.5f}, {1.0f, 0.0f, -40.0f}, {-1.0f, 0.0f, -40.0f}};
  const Primitive quad = test::make_primitive(pos, {0, 1, 2, 0, 2, 3});
  const RasterDraw draw = test::draw_of(quad, test::world_to_clip(cam), 0, false);
  JobSystem jobs(2);
  TiledRasterizer r;
  r.render_visibility(jobs, kInterpW, kInterpH, 32, {&draw, 1});

  int checked = 0;
  double max_b = 0.0, max_d = 0.0;
  for (int y = 0; y < kInterpH; ++y)
    for (int x = 0; x < kInterpW; ++x) {
      const uint32_t id = r.visibility().triangle[r.visibility().index(x, y)];
      if (id == kNoTriangle) continue;
      const TriangleRef ref = r.ref(id);
      REQUIRE(ref.triangle_index < 2);
      CHECK(ref.front_facing);
      const glm::vec3 v[3] = {pos[quad.indices[3 * ref.triangle_index]], pos[quad.indices[3 * ref.triangle_index + 1]],
                              pos[quad.indices[3 * ref.triangle_index + 2]]};
      const double px = x + 0.5, py = y + 0.5;
      const Barycentrics b = r.barycentrics(id, float(px), float(py));
      const glm::dvec3 expected = analytic(cam, v, px, py);
      max_b = std::max(max_b, glm::length(glm::dvec3(b.b) - expected));
      const double h = 0.01;
      const glm::dvec3 fdx = (analytic(cam, v, px + h, py) - analytic(cam, v, px - h, py)) / (2 * h);
      const glm::dvec3 fdy = (analytic(cam, v, px, py + h) - analytic(cam, v, px, py - h)) / (2 * h);
      for (int i = 0; i < 3; ++i) {
        max_d = std::max(max_d, std::abs(b.ddx[i] - fdx[i]) / (std::abs(fdx[i]) + 1e-4));
        max_d = std::max(max_d, std::abs(b.ddy[i] - fdy[i]) / (std::abs(fdy[i]) + 1e-4));
      }
      ++checked;
    }
  CHECK(checked > 3000);
  CHECK(max_b < 1e-4);
  CHECK(max_d < 2e-3);
}

TEST_CASE("barycentrics refer to the original triangle when it is clipped, and extend beyond its edges") {
  // Crosses the near plane: the visible part is a clipped polygon, yet weights
  // are relative to the original (partly invisible) vertices.
  const Camera cam = Camera::look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 1.2f, float(kInterpW) / kInterpH, 0.1f);
  const glm::vec3 v[3] = {{-2.0f, -1.0f, 1.0f}, {2.0f, -1.0f, -8.0f}, {-1.0f, 2.0f, -8.0f}};
  const Primitive tri = test::make_primitive({v[0], v[1], v[2]}, {0, 1, 2});
  const RasterDraw draw = test::draw_of(tri, test::world_to_clip(cam), 0);
  JobSystem jobs(1);
  TiledRasterizer r;
  const RasterStats& stats = r.render_visibility(jobs, kInterpW, kInterpH, 32, {&draw, 1});
  REQUIRE(stats.triangles_clipped == 1);
  uint32_t id = kNoTriangle;
  int checked = 0;
  double max_b = 0.0;
  for (int y = 0; y < kInterpH; ++y)
    for (int x = 0; x < kInterpW; ++x) {
      const uint32_t pixel_id = r.visibility().triangle[r.visibility().index(x, y)];
      if (pixel_id == kNoTriangle) continue;
      if (id == kNoTriangle) id = pixel_id;
      CHECK(pixel_id == id);  // all clipped pieces share the original's id
      const glm::dvec3 expected = analytic(cam, v, x + 0.5, y + 0.5);
      max_b = std::max(max_b, glm::length(glm::dvec3(r.barycentrics(id, x + 0.5f, y + 0.5f).b) - expected));
      ++checked;
    }
  CHECK(checked > 1000);
  CHECK(max_b < 1e-4);
  // Outside the triangle (left of the screen's visible part): weights
  // extrapolate the plane and derivatives stay exact.
  const double px = 3.5, py = 3.5;
  REQUIRE(r.visibility().triangle[r.visibility().index(3, 3)] == kNoTriangle);
  const Barycentrics b = r.barycentrics(id, float(px), float(py));
  const glm::dvec3 expected = analytic(cam, v, px, py);
  CHECK(glm::length(glm::dvec3(b.b) - expected) < 1e-4);
  const glm::dvec3 fdx = (analytic(cam, v, px + 0.25, py) - analytic(cam, v, px - 0.25, py)) / 0.5;
  for (int i = 0; i < 3; ++i) CHECK(b.ddx[i] == doctest::Approx(fdx[i]).epsilon(2e-3));
}

}  // namespace
}  // namespace cr

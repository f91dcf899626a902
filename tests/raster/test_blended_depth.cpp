// Blended pass (order, occlusion), back-to-front sorting, depth-only pass, statistics.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "engine/raster/blend_order.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kBlendW = 64, kBlendH = 48;

Primitive rect(float x0, float y0, float x1, float y1, float z) {
  return test::make_primitive({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {0, 1, 2, 0, 2, 3});
}

TEST_CASE("blended fragments arrive per pixel in the given order and only in front of opaque depth") {
  const glm::mat4 m = test::pixel_to_clip(kBlendW, kBlendH);
  const Primitive opaque = rect(0, 0, 32, 48, 0.5f);
  const Primitive b0 = rect(4, 4, 60, 44, 0.3f), b1 = rect(4, 4, 60, 44, 0.7f), b2 = rect(4, 4, 60, 44, 0.6f);
  const RasterDraw opaque_draw = test::draw_of(opaque, m, 0);
  const RasterDraw blended[] = {test::draw_of(b0, m, 10), test::draw_of(b1, m, 11), test::draw_of(b2, m, 12)};
  for (unsigned threads : {1u, 3u}) {
    CAPTURE(threads);
    JobSystem jobs(threads);
    TiledRasterizer r;
    r.render_visibility(jobs, kBlendW, kBlendH, 16, {&opaque_draw, 1});
    std::vector<std::vector<uint32_t>> seen(kBlendW * kBlendH);
    int bad_weights = 0;
    const RasterStats& stats = r.render_blended(jobs, blended, [&](int x, int y, uint32_t id, const Barycentrics& b, float) {
      seen[size_t(y) * kBlendW + x].push_back(r.ref(id).draw_index);
      bad_weights += std::abs(b.b.x + b.b.y + b.b.z - 1.0f) > 1e-5f;
    });
    CHECK(bad_weights == 0);
    CHECK(seen[size_t(10) * kBlendW + 10] == std::vector<uint32_t>{11, 12});      // behind opaque: b0 hidden
    CHECK(seen[size_t(10) * kBlendW + 40] == std::vector<uint32_t>{10, 11, 12});  // no opaque
    CHECK(seen[size_t(1) * kBlendW + 40].empty());
    CHECK(stats.pixels_passed == uint64_t(28 * 40 * 2 + 28 * 40 * 3));
    // The opaque visibility (and its ids) are untouched by the blended pass.
    CHECK(r.ref(r.visibility().triangle[r.visibility().index(10, 10)]).draw_index == 0);
  }
}

TEST_CASE("back-to-front order sorts by view depth of the centres, ties in submission order") {
  const std::vector<glm::dvec3> centres{{0, 0, -5}, {0, 0, -20}, {3, 1, -5}, {0, 0, 4}, {0, 0, -20}};
  const std::vector<uint32_t> order = back_to_front_order(centres, {0.0, 0.0, 0.0}, {0.0f, 0.0f, -1.0f});
  CHECK(order == std::vector<uint32_t>{1, 4, 0, 2, 3});
}

TEST_CASE("depth-only pass renders both faces with the same fill and depth as the visibility pass") {
  constexpr int S = 96;
  const glm::mat4 m = test::pixel_to_clip(S, S);
  // A sloped triangle (z from 0.1 to 0.9) and a back-facing one in front of part of it.
  const Primitive slope = test::make_primitive({{5, 90, 0.1f}, {90, 90, 0.9f}, {40, 3, 0.5f}}, {0, 1, 2});
  const Primitive back = test::make_primitive({{10, 10, 0.95f}, {30, 60, 0.95f}, {60, 20, 0.95f}}, {0, 1, 2});
  std::vector<RasterDraw> draws{test::draw_of(slope, m, 0, false), test::draw_of(back, m, 1, false)};
  JobSystem jobs(2);
  TiledRasterizer r;
  std::vector<float> depth;
  const RasterStats& stats = r.render_depth(jobs, S, 32, draws, depth);
  REQUIRE(depth.size() == size_t(S) * S);
  CHECK(stats.triangles_culled == 0);
  CHECK(depth[size_t(30) * S + 30] == 0.95f);  // the back face casts too
  // Linear depth of the slope (orthographic): z = 0.1 + 0.8 (x - 5) / 85 along y = 90 ... as a plane.
  const glm::dvec3 p0(5, 90, 0.1), p1(90, 90, 0.9), p2(40, 3, 0.5);
  const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
  const auto plane_z = [&](double x, double y) { return p0.z - (n.x * (x - p0.x) + n.y * (y - p0.y)) / n.z; };
  CHECK(depth[size_t(80) * S + 50] == doctest::Approx(plane_z(50.5, 80.5)).epsilon(1e-6));
  CHECK(depth[size_t(2) * S + 2] == 0.0f);

  // Same samples and bits as the visibility pass with both faces drawn.
  for (RasterDraw& d : draws) d.double_sided = true;
  r.render_visibility(jobs, S, S, 16, draws);
  CHECK(std::memcmp(depth.data(), r.visibility().depth.data(), depth.size() * sizeof(float)) == 0);
}

TEST_CASE("statistics count triangles, tile pairs and pixels") {
  const glm::mat4 m = test::pixel_to_clip(kBlendW, kBlendH);
  const Primitive a = rect(8, 8, 40, 24, 0.5f);    // 32 x 16 samples, spans tiles (0..2, 0..1) of 16
  const Primitive hidden = rect(8, 8, 24, 24, 0.25f);  // behind a
  const RasterDraw draws[] = {test::draw_of(a, m, 0), test::draw_of(hidden, m, 1)};
  JobSystem jobs(2);
  TiledRasterizer r;
  const RasterStats& s = r.render_visibility(jobs, kBlendW, kBlendH, 16, draws);
  CHECK(s.triangles_in == 4);
  CHECK(s.triangles_visible == 4);
  CHECK(s.screen_triangles == 4);
  CHECK(s.pixels_covered == 32 * 16 + 16 * 16);
  CHECK(s.pixels_passed == 32 * 16);
  CHECK(s.tiles_x == 4);
  CHECK(s.tiles_y == 3);
  REQUIRE(s.tiles.size() == 12);
  uint64_t pairs = 0, covered = 0, passed = 0;
  for (const TileStats& t : s.tiles) {
    pairs += t.triangles;
    covered += t.pixels_covered;
    passed += t.pixels_passed;
  }
  CHECK(pairs == s.tile_triangle_pairs);
  CHECK(covered == s.pixels_covered);
  CHECK(passed == s.pixels_passed);
  CHECK(s.tiles[3].triangles == 0);  // tile (3, 0) is empty
  CHECK(s.tiles[0].pixels_covered == 8 * 8 + 8 * 8);
}

}  // namespace
}  // namespace cr

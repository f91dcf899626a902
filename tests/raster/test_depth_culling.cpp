// Depth test order, back-face culling (double-sided, mirrored) and alpha-mask coverage.
#include <doctest/doctest.h>

#include <atomic>

#include "engine/core/error.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kCullW = 64, kCullH = 64;

Primitive culling_rect(float x0, float y0, float x1, float y1, float z) {
  return test::make_primitive({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {0, 1, 2, 0, 2, 3});
}

uint32_t draw_at(const TiledRasterizer& r, int x, int y) {
  const uint32_t id = r.visibility().triangle[r.visibility().index(x, y)];
  return id == kNoTriangle ? kNoTriangle : r.ref(id).draw_index;
}

TEST_CASE("nearer surface wins regardless of order; equal depth keeps the first submitted") {
  const glm::mat4 m = test::pixel_to_clip(kCullW, kCullH);
  const Primitive far_rect = culling_rect(4, 4, 40, 40, 0.25f);
  const Primitive near_rect = culling_rect(20, 20, 60, 60, 0.75f);  // reversed-Z: larger is nearer
  JobSystem jobs(2);
  TiledRasterizer r;
  for (bool near_first : {false, true}) {
    CAPTURE(near_first);
    std::vector<RasterDraw> draws{test::draw_of(far_rect, m, 0), test::draw_of(near_rect, m, 1)};
    if (near_first) std::swap(draws[0], draws[1]);
    r.render_visibility(jobs, kCullW, kCullH, 16, draws);
    CHECK(draw_at(r, 10, 10) == 0);
    CHECK(draw_at(r, 30, 30) == 1);
    CHECK(draw_at(r, 50, 50) == 1);
    CHECK(draw_at(r, 2, 2) == kNoTriangle);
    CHECK(r.visibility().depth[r.visibility().index(30, 30)] == 0.75f);
    CHECK(r.visibility().depth[r.visibility().index(2, 2)] == 0.0f);
  }
  const Primitive same = culling_rect(4, 4, 40, 40, 0.25f);
  const RasterDraw draws[] = {test::draw_of(far_rect, m, 7), test::draw_of(same, m, 8)};
  r.render_visibility(jobs, kCullW, kCullH, 16, draws);
  CHECK(draw_at(r, 10, 10) == 7);
  CHECK(draw_at(r, 39, 39) == 7);
}

TEST_CASE("back faces are culled unless double-sided; mirrored draws flip the front side") {
  // Counter-clockwise as seen on screen (NDC, y up) is the glTF front face.
  const Primitive ccw = test::make_primitive({{8, 40, 0.5f}, {40, 40, 0.5f}, {24, 8, 0.5f}}, {0, 1, 2});
  const Primitive cw = test::make_primitive({{8, 40, 0.5f}, {24, 8, 0.5f}, {40, 40, 0.5f}}, {0, 1, 2});
  const glm::mat4 m = test::pixel_to_clip(kCullW, kCullH);
  JobSystem jobs(1);
  TiledRasterizer r;
  struct Case {
    const Primitive* p;
    bool double_sided, mirrored, visible, front;
  };
  const Case cases[] = {
      {&ccw, false, false, true, true},  {&cw, false, false, false, false}, {&cw, true, false, true, false},
      {&ccw, true, false, true, true},   {&ccw, false, true, false, false}, {&cw, false, true, true, true},
      {&ccw, true, true, true, false},
  };
  for (const Case& c : cases) {
    CAPTURE(c.p == &ccw);
    CAPTURE(c.double_sided);
    CAPTURE(c.mirrored);
    RasterDraw d = test::draw_of(*c.p, m, 3, c.double_sided);
    d.mirrored = c.mirrored;
    const RasterStats& stats = r.render_visibility(jobs, kCullW, kCullH, 32, {&d, 1});
    CHECK(stats.triangles_culled == (c.visible ? 0u : 1u));
    const uint32_t id = r.visibility().triangle[r.visibility().index(24, 30)];
    REQUIRE((id != kNoTriangle) == c.visible);
    if (c.visible) CHECK(r.ref(id).front_facing == c.front);
  }
}

TEST_CASE("alpha-mask coverage is asked only where depth passes, and discards reveal what is behind") {
  const glm::mat4 m = test::pixel_to_clip(kCullW, kCullH);
  const Primitive back = culling_rect(0, 0, 64, 64, 0.2f);
  const Primitive masked = culling_rect(8, 8, 56, 56, 0.5f);
  const Primitive front = culling_rect(0, 0, 32, 64, 0.8f);  // covers the left half of the masked rect
  RasterDraw draws[] = {test::draw_of(back, m, 0), test::draw_of(front, m, 1), test::draw_of(masked, m, 2)};
  draws[2].alpha_mask = true;
  JobSystem jobs(2);
  TiledRasterizer r;
  std::atomic<int> calls{0};
  // Keep the samples where the third weight is small: splits the visible part
  // of the masked rect into kept and discarded samples.
  const CoverageFn coverage = [&](uint32_t id, const Barycentrics& b) {
    ++calls;
    CHECK(r.ref(id).draw_index == 2);
    return b.b.z < 0.3f;
  };
  r.render_visibility(jobs, kCullW, kCullH, 16, draws, coverage);
  // Masked samples not hidden by `front`: x in [32, 56), y in [8, 56).
  CHECK(calls.load() == 24 * 48);
  int kept = 0, discarded = 0;
  for (int y = 8; y < 56; ++y)
    for (int x = 32; x < 56; ++x) {
      const uint32_t id = r.visibility().triangle[r.visibility().index(x, y)];
      const Barycentrics b = r.barycentrics(id, x + 0.5f, y + 0.5f);
      if (r.ref(id).draw_index == 2) {
        ++kept;
        CHECK(b.b.z < 0.3f);
      } else {
        ++discarded;
        CHECK(r.ref(id).draw_index == 0);
      }
    }
  CHECK(kept > 100);
  CHECK(discarded > 100);
  CHECK_THROWS_AS(r.render_visibility(jobs, kCullW, kCullH, 16, draws), Error);  // mask without a coverage function
}

}  // namespace
}  // namespace cr

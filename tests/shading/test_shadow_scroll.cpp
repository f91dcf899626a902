// Scrolling the sun's shadow map under a moving camera (shadow_scroll.h):
// which texels come into view, the shift itself, when a map may scroll, and
// that a scrolled map equals a full render of the same projection.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/shading/shadow_scroll.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

bool in_rects(const std::vector<PixelRect>& rects, int x, int y) {
  for (const PixelRect& r : rects)
    if (x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1) return true;
  return false;
}

glm::vec3 scroll_sun_from(float elevation_deg, float azimuth_deg) {
  const float e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}

// A ground of 200 m with a field of boxes of several heights: casters that
// cross many tiles and texel edges at a low sun.
struct Terrain {
  std::vector<Primitive> parts;
  glm::vec3 lo{-100.0f, 0.0f, -100.0f}, hi{100.0f, 12.0f, 100.0f};

  Terrain() {
    parts.push_back(test::make_primitive({{-100, 0, -100}, {100, 0, -100}, {100, 0, 100}, {-100, 0, 100}},
                                         {0, 2, 1, 0, 3, 2}));
    for (int i = 0; i < 256; ++i) {  // a 16 x 16 field, so every strip that comes into view has casters
      const float x = -90.0f + 11.3f * float(i % 16), z = -90.0f + 11.7f * float(i / 16);
      const float s = 1.5f + 0.4f * float(i % 3), h = 2.0f + float(i % 4) * 2.5f;
      parts.push_back(test::make_primitive({{x - s, 0, z - s}, {x + s, 0, z - s}, {x + s, 0, z + s}, {x - s, 0, z + s},
                                            {x - s, h, z - s}, {x + s, h, z - s}, {x + s, h, z + s}, {x - s, h, z + s}},
                                           {0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6,
                                            3, 0, 4, 3, 4, 7, 4, 5, 6, 4, 6, 7}));
    }
  }

  // The parts, or with `regions` only those whose vertices' box reaches one
  // of them through region_projection.
  std::vector<RasterDraw> draws(const ShadowMap& map, const std::vector<PixelRect>& regions = {}) const {
    // World -> clip relative to the map's origin, composed in double.
    glm::dmat4 t(1.0);
    t[3] = glm::dvec4(-map.origin, 1.0);
    const glm::mat4 m(glm::dmat4(map.light_view_proj) * t);
    std::vector<RasterDraw> d;
    for (size_t i = 0; i < parts.size(); ++i) {
      bool reaches = regions.empty();
      for (const PixelRect& r : regions) {
        const glm::mat4 clip = region_projection(map, r);
        glm::vec2 lo(1e30f), hi(-1e30f);
        for (const glm::vec3& p : parts[i].positions) {
          const glm::vec4 c = clip * glm::vec4(glm::vec3(glm::dvec3(p) - map.origin), 1.0f);
          lo = glm::min(lo, glm::vec2(c));
          hi = glm::max(hi, glm::vec2(c));
        }
        reaches |= hi.x >= -1.0f && lo.x <= 1.0f && hi.y >= -1.0f && lo.y <= 1.0f;
      }
      if (reaches) d.push_back(test::draw_of(parts[i], m, uint32_t(i)));
    }
    return d;
  }
};

Camera camera_at(int frame) {
  // A low flight that turns: both the position and the view sphere's centre move.
  const float t = float(frame);
  const glm::vec3 eye(-20.0f + 1.7f * t, 4.0f + 0.2f * t, 30.0f - 2.3f * t);
  const glm::vec3 target(eye.x - 30.0f + 3.0f * t, 1.0f, eye.z - 60.0f);
  return Camera::look_at(eye, target, glm::radians(60.0f), 16.0f / 9.0f, 0.1f);
}

}  // namespace

TEST_CASE("shadow scroll: the exposed texels are exactly those whose source lies outside the old map") {
  constexpr int S = 12;
  for (int dx = -S + 1; dx < S; ++dx)
    for (int dy = -S + 1; dy < S; ++dy) {
      const std::vector<PixelRect> rects = exposed_texels(S, dx, dy);
      int wrong = 0;
      for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
          const int sx = x + dx, sy = y - dy;  // its source texel
          const bool outside = sx < 0 || sx >= S || sy < 0 || sy >= S;
          wrong += outside != in_rects(rects, x, y);
        }
      CAPTURE(dx);
      CAPTURE(dy);
      CHECK(wrong == 0);
      CHECK(rects.size() == size_t(dx != 0) + size_t(dy != 0));
    }
}

TEST_CASE("shadow scroll: exposed tiles are whole tiles covering the exposed texels") {
  constexpr int S = 100, kTile = 16;  // the last tile row and column are partial
  for (auto [dx, dy] : {std::pair{3, 0}, {-5, 7}, {0, -40}, {99, 99}}) {
    const std::vector<PixelRect> texels = exposed_texels(S, dx, dy), tiles = exposed_tiles(S, kTile, dx, dy);
    REQUIRE(texels.size() == tiles.size());
    for (size_t i = 0; i < tiles.size(); ++i) {
      CHECK((tiles[i].x0 % kTile == 0 && tiles[i].y0 % kTile == 0));
      CHECK(((tiles[i].x1 + 1) % kTile == 0 || tiles[i].x1 == S - 1));
      CHECK(((tiles[i].y1 + 1) % kTile == 0 || tiles[i].y1 == S - 1));
      CHECK((tiles[i].x0 <= texels[i].x0 && tiles[i].y0 <= texels[i].y0));
      CHECK((tiles[i].x1 >= texels[i].x1 && tiles[i].y1 >= texels[i].y1));
      CHECK(tiles[i].x1 - tiles[i].x0 < texels[i].x1 - texels[i].x0 + 2 * kTile);
    }
  }
}

TEST_CASE("shadow scroll: the scrolled image holds each kept texel's old value, for 1 and 3 threads") {
  constexpr int S = 70;
  std::vector<float> from(S * S);
  test::Random rng(7);
  for (float& v : from) v = rng.next();
  for (unsigned threads : {1u, 3u}) {
    JobSystem jobs(threads);
    for (auto [dx, dy] : {std::pair{0, 0}, {5, -3}, {-9, 11}, {69, 0}, {0, -69}}) {
      std::vector<float> to(S * S, -1.0f);
      scroll_depth(jobs, from, S, dx, dy, to);
      int wrong = 0, untouched = 0;
      for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
          const int sx = x + dx, sy = y - dy;
          const float v = to[size_t(y) * S + x];
          if (sx < 0 || sx >= S || sy < 0 || sy >= S)
            untouched += v == -1.0f;
          else
            wrong += v != from[size_t(sy) * S + sx];
        }
      CHECK(wrong == 0);
      CHECK(untouched == S * S - (S - std::abs(dx)) * (S - std::abs(dy)));
    }
  }
}

TEST_CASE("shadow scroll: a moving camera under a still sun scrolls, anything else renders whole") {
  const glm::vec3 sun = scroll_sun_from(20.0f, 40.0f);
  const glm::vec3 lo(-100.0f, 0.0f, -100.0f), hi(100.0f, 10.0f, 100.0f);
  const ShadowFit f0 = fit_shadow_view(camera_at(0), sun, 60.0f, 512, lo, hi);
  const double margin = -f0.need_min;
  const ShadowUpdate first = plan_shadow_update(ShadowMap{}, f0, 1, margin);
  CHECK_FALSE(first.scroll);  // nothing to scroll from
  const ShadowMap& m0 = first.map;
  CHECK(m0.depth_min == doctest::Approx(f0.need_min - margin));
  CHECK(m0.depth_max == doctest::Approx(f0.need_max + margin));

  const ShadowFit f1 = fit_shadow_view(camera_at(1), sun, 60.0f, 512, lo, hi);
  const ShadowUpdate next = plan_shadow_update(m0, f1, 1, margin);
  REQUIRE(next.scroll);
  CHECK(next.dx == f1.grid_x - f0.grid_x);
  CHECK(next.dy == f1.grid_y - f0.grid_y);
  CHECK((next.dx != 0 || next.dy != 0));
  // It keeps the depth frame it scrolls from: stored depths keep their meaning.
  CHECK(next.map.origin_depth == m0.origin_depth);
  CHECK(next.map.depth_min == m0.depth_min);
  CHECK(next.map.depth_max == m0.depth_max);
  CHECK(next.map.light_view_proj[0] == m0.light_view_proj[0]);
  CHECK(next.map.light_view_proj[2] == m0.light_view_proj[2]);

  // A step away from the sun leaves a map without margin, not one with it.
  Camera away = camera_at(0);
  away.position -= glm::dvec3(sun) * 5.0;
  const ShadowFit f_away = fit_shadow_view(away, sun, 60.0f, 512, lo, hi);
  CHECK_FALSE(plan_shadow_update(plan_shadow_update(ShadowMap{}, f0, 1, 0.0).map, f_away, 1, 0.0).scroll);
  CHECK(plan_shadow_update(m0, f_away, 1, margin).scroll);
  // Another sun, another size, another PCF radius, a jump past the map.
  CHECK_FALSE(plan_shadow_update(m0, fit_shadow_view(camera_at(1), scroll_sun_from(21.0f, 40.0f), 60.0f, 512, lo, hi), 1,
                                 margin).scroll);
  CHECK_FALSE(plan_shadow_update(m0, fit_shadow_view(camera_at(1), sun, 60.0f, 256, lo, hi), 1, margin).scroll);
  CHECK_FALSE(plan_shadow_update(m0, f1, 2, margin).scroll);
  Camera far = camera_at(0);
  far.position += glm::dvec3(400.0, 0.0, 0.0);
  CHECK_FALSE(plan_shadow_update(m0, fit_shadow_view(far, sun, 60.0f, 512, lo, hi), 1, margin).scroll);
}

TEST_CASE("shadow scroll: a map scrolled over ten frames equals a full render of the same projection") {
  const Terrain terrain;
  const glm::vec3 sun = scroll_sun_from(9.0f, 155.0f);
  constexpr int S = 512, kTile = 32;
  JobSystem jobs(2);
  TiledRasterizer scrolled_raster, full_raster;
  ShadowMap map;
  int scrolls = 0;
  for (int frame = 0; frame < 10; ++frame) {
    CAPTURE(frame);
    const ShadowFit fit = fit_shadow_view(camera_at(frame), sun, 80.0f, S, terrain.lo, terrain.hi);
    ShadowUpdate u = plan_shadow_update(map, fit, 1, -fit.need_min);
    std::vector<PixelRect> regions;
    if (u.scroll) {
      ++scrolls;
      scroll_depth(jobs, map.depth, S, u.dx, u.dy, u.map.depth);
      regions = exposed_tiles(S, kTile, u.dx, u.dy);
    }
    map = std::move(u.map);
    if (!u.scroll || !regions.empty()) {
      const std::vector<RasterDraw> casters = terrain.draws(map, regions);
      if (u.scroll) CHECK(casters.size() < terrain.parts.size());  // the strips miss some boxes
      scrolled_raster.render_depth(jobs, S, kTile, casters, map.depth, {}, regions);
    }

    std::vector<float> full;
    full_raster.render_depth(jobs, S, kTile, terrain.draws(map), full);
    // The same projection but another origin: the texels' depths agree to
    // float rounding; a texel centre exactly on an edge may fall either way.
    int flipped = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < full.size(); ++i) {
      const float d = std::abs(full[i] - map.depth[i]);
      if (d > 1e-3f)
        ++flipped;
      else
        worst = std::max(worst, d);
    }
    CHECK(flipped <= S * S / 10000);
    CHECK(worst <= 1e-6f);
  }
  CHECK(scrolls == 9);
}

}  // namespace cr

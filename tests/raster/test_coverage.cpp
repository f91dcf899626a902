// Coverage: watertight meshes (every sample of a shared-edge mesh hit exactly
// once) and the top-left fill rule on samples exactly on shared edges.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/core/math_constants.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

using test::Random;

// A (cells x cells) grid over [lo, hi]^2 in pixels, interior vertices jittered,
// each cell split along a random diagonal. The jitter is small enough that no
// triangle folds over (checked by the test), so the triangles tile the square.
Primitive jittered_grid(int cells, float lo, float hi, uint64_t seed) {
  Random rng(seed);
  std::vector<glm::vec3> pos;
  const float step = (hi - lo) / float(cells);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      float x = lo + step * float(i), y = lo + step * float(j);
      if (i > 0 && i < cells) x += rng.range(-0.25f, 0.25f) * step;
      if (j > 0 && j < cells) y += rng.range(-0.25f, 0.25f) * step;
      pos.emplace_back(x, y, 0.5f);
    }
  std::vector<uint32_t> idx;
  const auto at = [cells](int i, int j) { return uint32_t(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (rng.next() < 0.5f)
        idx.insert(idx.end(), {a, b, c, a, c, d});
      else
        idx.insert(idx.end(), {a, b, d, b, c, d});
    }
  return test::make_primitive(std::move(pos), std::move(idx));
}

TEST_CASE("jittered grid is watertight: every sample inside hit exactly once") {
  constexpr int W = 256, H = 256;
  const float lo = 10.3f, hi = 240.7f;
  const Primitive grid = jittered_grid(60, lo, hi, 7);  // 7200 triangles
  for (size_t t = 0; t < grid.indices.size(); t += 3) {
    const glm::vec3 a = grid.positions[grid.indices[t]], b = grid.positions[grid.indices[t + 1]],
                    c = grid.positions[grid.indices[t + 2]];
    REQUIRE((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0.0f);
  }
  const RasterDraw draw = test::draw_of(grid, test::pixel_to_clip(W, H), 0);
  JobSystem jobs(2);
  for (int tile : {8, 64}) {
    CAPTURE(tile);
    const std::vector<int> hits = test::count_hits(jobs, W, H, tile, {&draw, 1});
    int wrong = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const float cx = x + 0.5f, cy = y + 0.5f;
        const int expected = (cx > lo && cx < hi && cy > lo && cy < hi) ? 1 : 0;
        wrong += hits[size_t(y) * W + x] != expected;
      }
    CHECK(wrong == 0);
  }
}

TEST_CASE("fan of thin triangles around a vertex is watertight") {
  constexpr int W = 256, H = 256;
  constexpr int N = 720;
  const glm::dvec2 c(128.37, 127.61);
  const double radius = 100.0;
  std::vector<glm::vec3> pos{{float(c.x), float(c.y), 0.5f}};
  for (int i = 0; i < N; ++i) {
    const double a = 2.0 * kPiD * i / N;
    pos.emplace_back(float(c.x + radius * std::cos(a)), float(c.y + radius * std::sin(a)), 0.5f);
  }
  std::vector<uint32_t> idx;
  for (int i = 0; i < N; ++i) idx.insert(idx.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % N)});
  const Primitive fan = test::make_primitive(pos, idx);
  const RasterDraw draw = test::draw_of(fan, test::pixel_to_clip(W, H), 0);
  JobSystem jobs(2);
  const std::vector<int> hits = test::count_hits(jobs, W, H, 32, {&draw, 1});

  // Signed distance of a sample to the N-gon (negative inside), from the vertices as given.
  const auto distance = [&](glm::dvec2 p) {
    double d = -1e30;
    for (int i = 0; i < N; ++i) {
      const glm::dvec2 a(pos[1 + i].x, pos[1 + i].y), b(pos[1 + (i + 1) % N].x, pos[1 + (i + 1) % N].y);
      const glm::dvec2 e = b - a, n = glm::normalize(glm::dvec2(e.y, -e.x));
      d = std::max(d, glm::dot(p - a, n) * (glm::dot(glm::dvec2(c) - a, n) > 0 ? -1.0 : 1.0));
    }
    return d;
  };
  int inside = 0, wrong = 0, multiple = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int h = hits[size_t(y) * W + x];
      multiple += h > 1;
      const double d = distance({x + 0.5, y + 0.5});
      if (std::abs(d) < 0.01) continue;  // within snapping distance of the outline
      inside += d < 0;
      wrong += h != (d < 0 ? 1 : 0);
    }
  CHECK(inside > 30000);
  CHECK(multiple == 0);
  CHECK(wrong == 0);
}

TEST_CASE("ground mesh crossing the near plane and guard band stays watertight") {
  constexpr int W = 320, H = 180;
  // Camera 2 cm above the ground looking down: the near plane cuts the ground
  // and nearby triangles project far beyond the guard band.
  const Camera cam = Camera::look_at({0.3, 0.02, 0.1}, {0.8, -0.4, -1.0}, 1.0f, float(W) / H, 0.1f);
  Random rng(3);
  constexpr int cells = 80;
  const float lo = -40.0f, step = 1.0f;
  std::vector<glm::vec3> pos;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      float x = lo + step * float(i), z = lo + step * float(j);
      if (i > 0 && i < cells) x += rng.range(-0.3f, 0.3f);
      if (j > 0 && j < cells) z += rng.range(-0.3f, 0.3f);
      pos.emplace_back(x, 0.0f, z);
    }
  std::vector<uint32_t> idx;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const uint32_t a = j * (cells + 1) + i, b = a + 1, c = a + cells + 2, d = a + cells + 1;
      idx.insert(idx.end(), {a, b, c, a, c, d});
    }
  const Primitive ground = test::make_primitive(pos, idx);
  const RasterDraw draw = test::draw_of(ground, test::world_to_clip(cam), 0);
  JobSystem jobs(2);
  const std::vector<int> hits = test::count_hits(jobs, W, H, 16, {&draw, 1});

  int covered = 0, wrong = 0, multiple = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int h = hits[size_t(y) * W + x];
      multiple += h > 1;
      const glm::dvec3 d = glm::dvec3(cam.ray_direction(x + 0.5f, y + 0.5f, W, H));
      // Near the horizon a tiny angular error is a long way on the ground: skip it.
      if (std::abs(d.y) < 2e-3) continue;
      int expected = 0;  // sky
      if (d.y < 0.0) {
        const glm::dvec3 p = cam.position + d * (-cam.position.y / d.y);
        const double depth = glm::dot(p - cam.position, glm::dvec3(cam.forward));
        const double edge = std::min(std::min(p.x - lo, lo + cells * step - p.x), std::min(p.z - lo, lo + cells * step - p.z));
        if (std::abs(depth - cam.znear) < 1e-3 || std::abs(edge) < 0.05) continue;
        expected = (depth > cam.znear && edge > 0) ? 1 : 0;
      }
      covered += expected;
      wrong += h != expected;
    }
  CHECK(covered > W * H / 6);
  CHECK(multiple == 0);
  CHECK(wrong == 0);
}

// Two triangles sharing the edge p-q; returns, per sample on the open edge,
// which of them (0 = first, 1 = second) owns it.
std::vector<int> edge_owners(glm::vec2 p, glm::vec2 q, glm::vec2 first_apex, glm::vec2 second_apex,
                             const std::vector<glm::ivec2>& samples, bool second_submitted_first) {
  constexpr int W = 16, H = 16;
  const Primitive a = test::make_primitive({{p, 0.5f}, {q, 0.5f}, {first_apex, 0.5f}}, {0, 1, 2});
  const Primitive b = test::make_primitive({{p, 0.5f}, {q, 0.5f}, {second_apex, 0.5f}}, {0, 1, 2});
  const glm::mat4 m = test::pixel_to_clip(W, H);
  std::vector<RasterDraw> draws{test::draw_of(a, m, 0), test::draw_of(b, m, 1)};
  if (second_submitted_first) std::swap(draws[0], draws[1]);
  JobSystem jobs(1);
  TiledRasterizer r;
  r.render_visibility(jobs, W, H, 8, draws);
  std::vector<int> owners;
  for (glm::ivec2 s : samples) {
    const uint32_t id = r.visibility().triangle[r.visibility().index(s.x, s.y)];
    owners.push_back(id == kNoTriangle ? -1 : int(r.ref(id).draw_index));
  }
  return owners;
}

TEST_CASE("top-left rule assigns samples on shared edges to exactly one triangle") {
  for (bool swapped : {false, true}) {
    CAPTURE(swapped);
    SUBCASE("horizontal edge: the triangle below owns it (top edge)") {
      std::vector<glm::ivec2> s;
      for (int x = 2; x <= 11; ++x) s.push_back({x, 5});
      const auto owners = edge_owners({1.5f, 5.5f}, {12.5f, 5.5f}, {7.0f, 1.0f}, {7.0f, 10.0f}, s, swapped);
      for (int o : owners) CHECK(o == 1);
    }
    SUBCASE("vertical edge: the triangle on the right owns it (left edge)") {
      std::vector<glm::ivec2> s;
      for (int y = 2; y <= 11; ++y) s.push_back({5, y});
      const auto owners = edge_owners({5.5f, 1.5f}, {5.5f, 12.5f}, {1.0f, 7.0f}, {10.0f, 7.0f}, s, swapped);
      for (int o : owners) CHECK(o == 1);
    }
    SUBCASE("diagonal edge: the upper-right triangle owns it (its left edge)") {
      std::vector<glm::ivec2> s;
      for (int k = 2; k <= 10; ++k) s.push_back({k, k});
      const auto owners = edge_owners({1.5f, 1.5f}, {11.5f, 11.5f}, {1.5f, 11.5f}, {11.5f, 1.5f}, s, swapped);
      for (int o : owners) CHECK(o == 1);
    }
    SUBCASE("anti-diagonal edge: the lower-right triangle owns it (its left edge)") {
      std::vector<glm::ivec2> s;
      for (int k = 2; k <= 11; ++k) s.push_back({k, 14 - k});
      const auto owners = edge_owners({1.5f, 13.5f}, {12.5f, 2.5f}, {1.5f, 2.5f}, {12.5f, 13.5f}, s, swapped);
      for (int o : owners) CHECK(o == 1);
    }
  }
}

}  // namespace
}  // namespace cr

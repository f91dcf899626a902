// Multisampled visibility: each sample is covered exactly when its position
// lies inside the triangle, coverage matches a half-plane's area, alpha-mask
// coverage is tested per sample, and the layers are bit-identical for any
// thread count and tile size.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kMsW = 32, kMsH = 24;

// A triangle far larger than the image whose edge from (x0, y0) to (x1, y1)
// (pixels) crosses it: the image sees the half-plane to the edge's right.
Primitive half_plane(glm::dvec2 p0, glm::dvec2 p1) {
  const glm::dvec2 d = glm::normalize(p1 - p0), n(-d.y, d.x);
  const glm::dvec2 a = p0 - 1000.0 * d, b = p0 + 1000.0 * d, c = p0 + 1000.0 * n;
  return test::make_primitive({glm::vec3(a.x, a.y, 0.5f), glm::vec3(b.x, b.y, 0.5f), glm::vec3(c.x, c.y, 0.5f)},
                              {0, 1, 2});
}

// Covered samples per pixel of a one-draw render.
std::vector<int> covered_samples(const TiledRasterizer& r) {
  const VisibilityBuffer& v = r.visibility();
  std::vector<int> n(size_t(v.width) * size_t(v.height), 0);
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
      for (int s = 0; s < v.pattern.count; ++s) n[v.index(x, y)] += v.sample_triangle(x, y, s) != kNoTriangle;
  return n;
}

// Which side of the directed edge p0 -> p1 point q is on (positive: the
// triangle's side in half_plane(), where the third vertex lies).
double side(glm::dvec2 p0, glm::dvec2 p1, glm::dvec2 q) {
  const glm::dvec2 d = p1 - p0;
  return d.x * (q.y - p0.y) - d.y * (q.x - p0.x);
}

TEST_CASE("multisampling: the standard patterns are centred and within the pixel") {
  for (int n : {1, 2, 4, 8}) {
    const SamplePattern p = sample_pattern(n);
    int sx = 0, sy = 0;
    for (int s = 0; s < n; ++s) {
      sx += p.x[size_t(s)];
      sy += p.y[size_t(s)];
      CHECK(std::abs(p.dx(s)) < 0.5f);
      CHECK(std::abs(p.dy(s)) < 0.5f);
    }
    CHECK(sx == 0);
    CHECK(sy == 0);
  }
  CHECK_THROWS_WITH(sample_pattern(3), doctest::Contains("1, 2, 4 or 8"));
}

TEST_CASE("multisampling: a sample is covered exactly when its position lies inside (random half-planes)") {
  JobSystem jobs(2);
  test::Random rng(5);
  for (int samples : {2, 4, 8}) {
    const SamplePattern pattern = sample_pattern(samples);
    for (int trial = 0; trial < 24; ++trial) {
      // Vertices on the 1/256 lattice, so the snapped edge is the exact one.
      auto lattice = [&](float lo, float hi) { return std::round(rng.range(lo, hi) * 256.0) / 256.0; };
      const glm::dvec2 p0(lattice(2, 30), lattice(2, 22)), p1(lattice(2, 30), lattice(2, 22));
      if (glm::length(p1 - p0) < 4.0) continue;
      const Primitive prim = half_plane(p0, p1);
      const RasterDraw d = test::draw_of(prim, test::pixel_to_clip(kMsW, kMsH), 0);
      TiledRasterizer r;
      r.render_visibility(jobs, kMsW, kMsH, 8, std::span(&d, 1), {}, samples);
      const VisibilityBuffer& v = r.visibility();
      int mismatches = 0, tested = 0;
      for (int y = 0; y < kMsH; ++y)
        for (int x = 0; x < kMsW; ++x)
          for (int s = 0; s < samples; ++s) {
            const glm::dvec2 q(x + 0.5 + pattern.dx(s), y + 0.5 + pattern.dy(s));
            const double e = side(p0, p1, q) / glm::length(p1 - p0);
            if (std::abs(e) < 1e-6) continue;  // on the edge: the top-left rule decides
            const bool inside = e > 0;
            const bool covered = v.sample_triangle(x, y, s) != kNoTriangle;
            mismatches += inside != covered;
            ++tested;
          }
      CAPTURE(samples);
      CAPTURE(trial);
      CHECK(tested > 0);
      CHECK(mismatches == 0);
    }
  }
}

TEST_CASE("multisampling: an axis-aligned half-plane's coverage is its area within half a sample, a quarter on average") {
  // The patterns have one sample per 1/N column and row, so a vertical or
  // horizontal edge at any sub-pixel position covers N * area +- 1/2 samples,
  // and over the edge's positions the error averages 1/4 sample.
  JobSystem jobs(1);
  for (int samples : {2, 4, 8}) {
    double edge_error[2] = {0.0, 0.0};
    for (int k = 0; k < 32; ++k) {
      const double e = 10.0 + (k + 0.5) / 32.0;  // never on a sample (multiples of 1/16 from the centre)
      for (bool vertical : {true, false}) {
        const Primitive prim = vertical ? half_plane({e, 0.0}, {e, 1.0}) : half_plane({1.0, e}, {0.0, e});
        const RasterDraw d = test::draw_of(prim, test::pixel_to_clip(kMsW, kMsH), 0);
        TiledRasterizer r;
        r.render_visibility(jobs, kMsW, kMsH, 16, std::span(&d, 1), {}, samples);
        const std::vector<int> n = covered_samples(r);
        for (int y = 0; y < kMsH; ++y)
          for (int x = 0; x < kMsW; ++x) {
            const double c = vertical ? x : y;  // the pixel spans [c, c + 1) across the edge
            // Covered side: x < e for the vertical edge (interior to the right
            // of the downward direction), y < e for the horizontal one.
            const double area = std::clamp(e - c, 0.0, 1.0);
            CAPTURE(samples);
            CAPTURE(e);
            CAPTURE(vertical);
            CHECK(std::abs(n[size_t(y) * kMsW + x] - samples * area) <= 0.5);
          }
        edge_error[vertical] += std::abs(n[vertical ? 10 : 10 * kMsW] - samples * (e - 10.0)) / 32.0;
      }
    }
    CAPTURE(samples);
    CHECK(edge_error[0] <= 0.25 + 1e-9);
    CHECK(edge_error[1] <= 0.25 + 1e-9);
  }
}

TEST_CASE("multisampling: alpha-mask coverage is asked at each sample, so mask edges get fractional coverage") {
  JobSystem jobs(2);
  // One triangle over the whole image with screen x = -1 + 128 b1 (affine:
  // w = 1), whose mask keeps x < 12.3 from the barycentrics at the sample.
  const Primitive tri = test::make_primitive({{-1.0f, -50.0f, 0.5f}, {127.0f, -50.0f, 0.5f}, {-1.0f, 200.0f, 0.5f}},
                                             {0, 1, 2});
  RasterDraw d = test::draw_of(tri, test::pixel_to_clip(kMsW, kMsH), 0);
  d.alpha_mask = true;
  TiledRasterizer r;
  const CoverageFn mask = [](uint32_t, const Barycentrics& b) { return -1.0f + 128.0f * b.b[1] < 12.3f; };
  r.render_visibility(jobs, kMsW, kMsH, 8, std::span(&d, 1), mask, 4);
  const std::vector<int> n = covered_samples(r);
  const SamplePattern p = sample_pattern(4);
  for (int y = 0; y < kMsH; ++y) {
    int expected = 0;
    for (int s = 0; s < 4; ++s) expected += 12.0 + 0.5 + p.dx(s) < 12.3;
    CHECK(n[size_t(y) * kMsW + 11] == 4);
    CHECK(n[size_t(y) * kMsW + 12] == expected);
    CHECK(n[size_t(y) * kMsW + 13] == 0);
  }
  CHECK(0 < n[12]);
  CHECK(n[12] < 4);
}

TEST_CASE("multisampling: blended triangles arrive once per pixel with the share of samples they cover") {
  JobSystem jobs(2);
  for (int samples : {2, 4, 8}) {
    const SamplePattern p = sample_pattern(samples);
    const double e = 12.3;  // a vertical edge: the half-plane x < e
    const Primitive prim = half_plane({e, 0.0}, {e, 1.0});
    const RasterDraw d = test::draw_of(prim, test::pixel_to_clip(kMsW, kMsH), 0);
    TiledRasterizer r;
    r.render_visibility(jobs, kMsW, kMsH, 8, {}, {}, samples);
    std::vector<int> calls(size_t(kMsW) * kMsH, 0);
    std::vector<float> coverage(size_t(kMsW) * kMsH, 0.0f);
    r.render_blended(jobs, std::span(&d, 1), [&](int x, int y, uint32_t, const Barycentrics&, float c) {
      ++calls[size_t(y) * kMsW + x];
      coverage[size_t(y) * kMsW + x] = c;
    });
    int expected = 0;
    for (int s = 0; s < samples; ++s) expected += 12.5 + p.dx(s) < e;
    CAPTURE(samples);
    for (int y = 0; y < kMsH; ++y) {
      CHECK(calls[size_t(y) * kMsW + 5] == 1);
      CHECK(coverage[size_t(y) * kMsW + 5] == 1.0f);
      CHECK(calls[size_t(y) * kMsW + 12] == (expected > 0 ? 1 : 0));
      CHECK(coverage[size_t(y) * kMsW + 12] == float(expected) / float(samples));
      CHECK(calls[size_t(y) * kMsW + 13] == 0);
    }
  }
}

TEST_CASE("multisampling: sample layers are bit-identical for 1..8 threads and tile sizes 8..256") {
  test::Random rng(3);
  Primitive soup;
  for (int t = 0; t < 2000; ++t) {
    const glm::vec3 c(rng.range(-5, kMsW + 5), rng.range(-5, kMsH + 5), rng.range(0.1f, 0.9f));
    for (int k = 0; k < 3; ++k) {
      soup.positions.push_back(c + glm::vec3(rng.range(-6, 6), rng.range(-6, 6), rng.range(-0.1f, 0.1f)));
      soup.indices.push_back(uint32_t(soup.positions.size() - 1));
    }
  }
  RasterDraw d = test::draw_of(soup, test::pixel_to_clip(kMsW, kMsH), 0);
  d.alpha_mask = true;
  const CoverageFn coverage = [](uint32_t, const Barycentrics& b) { return b.b[1] < 0.7f; };
  for (int samples : {4, 8}) {
    JobSystem one(1);
    TiledRasterizer ref;
    ref.render_visibility(one, kMsW, kMsH, 64, std::span(&d, 1), coverage, samples);
    for (unsigned threads = 1; threads <= 8; ++threads) {
      JobSystem jobs(threads);
      for (int tile : {8, 32, 256}) {
        TiledRasterizer r;
        r.render_visibility(jobs, kMsW, kMsH, tile, std::span(&d, 1), coverage, samples);
        CAPTURE(samples);
        CAPTURE(threads);
        CAPTURE(tile);
        // Every sample's id and depth (a pixel whose samples agree keeps
        // their mean depth), whatever the tiles it was listed by.
        const VisibilityBuffer &a = r.visibility(), &b = ref.visibility();
        int differ = 0;
        for (int y = 0; y < kMsH; ++y)
          for (int x = 0; x < kMsW; ++x)
            for (int s = 0; s < samples; ++s) {
              const float za = a.sample_depth(x, y, s), zb = b.sample_depth(x, y, s);
              differ += a.sample_triangle(x, y, s) != b.sample_triangle(x, y, s) || std::memcmp(&za, &zb, sizeof za) != 0;
            }
        CHECK(differ == 0);
        CHECK(a.triangle == b.triangle);
        CHECK(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0);
      }
    }
  }
}

}  // namespace
}  // namespace cr

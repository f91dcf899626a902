// Bit-identical results for any thread count and tile size.
#include <doctest/doctest.h>

#include <cstring>

#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kDetW = 300, kDetH = 200;

// Overlapping random triangles in a perspective view: many depth ties near
// edges, clipped triangles, alpha-masked draws.
struct RandomScene {
  Primitive a, b;
  Camera cam = Camera::look_at({0.0, 1.0, 3.0}, {0.0, 0.0, -5.0}, 1.1f, float(kDetW) / kDetH, 0.1f);

  explicit RandomScene(uint64_t seed) {
    test::Random rng(seed);
    for (Primitive* p : {&a, &b}) {
      for (int t = 0; t < 3000; ++t) {
        const glm::vec3 c(rng.range(-8, 8), rng.range(-3, 3), rng.range(-20, 3));
        for (int k = 0; k < 3; ++k) {
          p->positions.push_back(c + glm::vec3(rng.range(-1.5f, 1.5f), rng.range(-1.5f, 1.5f), rng.range(-1.5f, 1.5f)));
          p->indices.push_back(uint32_t(p->positions.size() - 1));
        }
      }
    }
  }
  std::vector<RasterDraw> draws() const {
    std::vector<RasterDraw> d{test::draw_of(a, test::world_to_clip(cam), 0, false),
                              test::draw_of(b, test::world_to_clip(cam), 1, true)};
    d[1].alpha_mask = true;
    return d;
  }
};

bool same_bits(const VisibilityBuffer& x, const VisibilityBuffer& y) {
  return x.depth.size() == y.depth.size() &&
         std::memcmp(x.depth.data(), y.depth.data(), x.depth.size() * sizeof(float)) == 0 &&
         x.triangle == y.triangle;
}

TEST_CASE("visibility buffer is bit-identical for 1, 2, 3, 8 threads and tile sizes 8..256") {
  const RandomScene scene(11);
  const std::vector<RasterDraw> draws = scene.draws();
  const CoverageFn coverage = [](uint32_t, const Barycentrics& b) { return b.b.y < 0.6f; };

  TiledRasterizer reference;
  JobSystem one(1);
  const RasterStats ref_stats = reference.render_visibility(one, kDetW, kDetH, 64, draws, coverage);
  CHECK(ref_stats.triangles_clipped > 0);
  CHECK(ref_stats.pixels_passed > uint64_t(kDetW * kDetH));

  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    JobSystem jobs(threads);
    for (int tile : {8, 16, 32, 64, 128, 256}) {
      CAPTURE(threads);
      CAPTURE(tile);
      TiledRasterizer r;
      const RasterStats& stats = r.render_visibility(jobs, kDetW, kDetH, tile, draws, coverage);
      CHECK(same_bits(r.visibility(), reference.visibility()));
      CHECK(stats.pixels_covered == ref_stats.pixels_covered);
      CHECK(stats.pixels_passed == ref_stats.pixels_passed);
    }
  }
}

TEST_CASE("a rasterizer reused across frames gives the same result as a fresh one") {
  const RandomScene first(1), second(2);
  JobSystem jobs(3);
  TiledRasterizer reused, fresh;
  const CoverageFn coverage = [](uint32_t, const Barycentrics& b) { return b.b.x > 0.2f; };
  reused.render_visibility(jobs, kDetW, kDetH, 32, first.draws(), coverage);
  reused.render_visibility(jobs, kDetW / 2, kDetH, 16, second.draws(), coverage);
  fresh.render_visibility(jobs, kDetW / 2, kDetH, 16, second.draws(), coverage);
  CHECK(same_bits(reused.visibility(), fresh.visibility()));
}

TEST_CASE("coverage callbacks may use the job system while tiles are rasterised") {
  // A thread waiting in a nested parallel_for helps with queued jobs, so it
  // may start another tile while its own is unfinished.
  const RandomScene scene(5);
  const std::vector<RasterDraw> draws = scene.draws();
  const auto keep = [](const Barycentrics& b) { return b.b.z < 0.7f; };
  JobSystem jobs(3);
  TiledRasterizer plain, nested;
  plain.render_visibility(jobs, kDetW, kDetH, 16, draws, [&](uint32_t, const Barycentrics& b) { return keep(b); });
  nested.render_visibility(jobs, kDetW, kDetH, 16, draws, [&](uint32_t, const Barycentrics& b) {
    jobs.parallel_for("inner", 2, 1, [](size_t, size_t) {});
    return keep(b);
  });
  CHECK(same_bits(plain.visibility(), nested.visibility()));
}

}  // namespace
}  // namespace cr

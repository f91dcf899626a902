// Throughput benchmark (prints figures; skipped in normal runs):
//   test_raster -tc="benchmark*" --no-skip
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>

#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int W = 1280, H = 720;

// ~200k triangles of ~4.6 pixels each, tiling the screen (jittered grid).
Primitive screen_grid() {
  test::Random rng(5);
  constexpr int nx = 400, ny = 250;
  std::vector<glm::vec3> pos;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const float jx = (i > 0 && i < nx) ? rng.range(-0.2f, 0.2f) : 0.0f;
      const float jy = (j > 0 && j < ny) ? rng.range(-0.2f, 0.2f) : 0.0f;
      pos.emplace_back((i + jx) * W / float(nx), (j + jy) * H / float(ny), 0.2f + 0.6f * rng.next());
    }
  std::vector<uint32_t> idx;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      idx.insert(idx.end(), {a, b, c, a, c, d});
    }
  return test::make_primitive(std::move(pos), std::move(idx));
}

// A 317 x 317 heightfield (~200k triangles) seen from above at an angle.
Primitive terrain() {
  constexpr int n = 317;
  std::vector<glm::vec3> pos;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = (i - n / 2) * 2.0f, z = (j - n / 2) * 2.0f;
      pos.emplace_back(x, 8.0f * std::sin(x * 0.05f) * std::cos(z * 0.04f) + 2.0f * std::sin(x * 0.3f + z * 0.2f), z);
    }
  std::vector<uint32_t> idx;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      idx.insert(idx.end(), {a, d, c, a, c, b});
    }
  return test::make_primitive(std::move(pos), std::move(idx));
}

void run(const char* name, const RasterDraw& draw, unsigned threads, int tile) {
  JobSystem jobs(threads);
  TiledRasterizer r;
  constexpr int warmup = 3, frames = 20;
  std::vector<double> times, cpu_times;
  std::map<std::string, double> stage_us;
  for (int f = 0; f < warmup + frames; ++f) {
    jobs.take_records();
    const std::clock_t c0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    r.render_visibility(jobs, W, H, tile, {&draw, 1});
    const auto t1 = std::chrono::steady_clock::now();
    const std::clock_t c1 = std::clock();
    if (f < warmup) continue;
    times.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    cpu_times.push_back(1e3 * double(c1 - c0) / CLOCKS_PER_SEC);
    for (const JobRecord& rec : jobs.take_records()) stage_us[rec.name] += rec.end_us - rec.begin_us;
  }
  const RasterStats& s = r.render_visibility(jobs, W, H, tile, {&draw, 1});
  // Wall time suffers on a shared machine; process CPU time (all threads) does less.
  std::sort(times.begin(), times.end());
  std::sort(cpu_times.begin(), cpu_times.end());
  const double ms = times[0];
  std::printf("%-12s threads %u tile %3d: wall best %6.2f median %6.2f ms, cpu median %6.2f ms/frame  %6.1f Mtris/s  %6.1f Mpix/s  (tris in %llu, visible %llu, "
              "pairs %llu, pixels %llu)  mean job ms/frame:",
              name, threads, tile, ms, times[times.size() / 2], cpu_times[cpu_times.size() / 2], s.triangles_in / ms / 1e3, s.pixels_covered / ms / 1e3,
              (unsigned long long)s.triangles_in, (unsigned long long)s.triangles_visible,
              (unsigned long long)s.tile_triangle_pairs, (unsigned long long)s.pixels_covered);
  for (const auto& [stage, us] : stage_us) std::printf(" %s %.2f", stage.c_str(), us / frames / 1e3);
  std::printf("\n");
}

TEST_CASE("benchmark: 200k triangles at 1280x720" * doctest::skip()) {
  const Primitive grid = screen_grid();
  const Primitive land = terrain();
  const RasterDraw grid_draw = test::draw_of(grid, test::pixel_to_clip(W, H), 0);
  const Camera cam = Camera::look_at({0.0, 60.0, 200.0}, {0.0, 0.0, 0.0}, 1.0f, float(W) / H, 0.1f);
  const RasterDraw land_draw = test::draw_of(land, test::world_to_clip(cam), 0, false);
  for (int tile : {32, 64})
    for (unsigned threads : {1u, 2u}) {
      run("screen-grid", grid_draw, threads, tile);
      run("terrain", land_draw, threads, tile);
    }
}

}  // namespace
}  // namespace cr

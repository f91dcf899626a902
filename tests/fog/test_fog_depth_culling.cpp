// Depth-aware culling: froxels behind the farthest surface of the pixels that
// can read them are skipped, and the image does not change.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kCullW = 96, kCullH = 64;
const glm::vec3 kCullSun(0.8f, 0.35f, 0.2f);

// Sky in the top quarter, "ground" below whose distance shrinks towards the
// bottom rows, and a near block (a wall 4 m away) on the left.
std::vector<float> ground_distances() {
  std::vector<float> d(size_t(kCullW) * kCullH);
  for (int y = 0; y < kCullH; ++y)
    for (int x = 0; x < kCullW; ++x) {
      float v = y < kCullH / 4 ? INFINITY : 2.0f + 24.0f * float(kCullH - y) / float(kCullH);
      if (x < 20 && y > 10) v = 4.0f;
      d[size_t(y) * kCullW + x] = v;
    }
  return d;
}

FogSceneSettings scene() {
  FogSceneSettings s = uniform_fog(0.04f, glm::vec3(0.9f), 0.5f);
  s.base_height = 0.0f;
  s.max_height = 10.0f;
  FogVolume v;
  v.center = {2, 2, -15};
  v.half_size = {3, 2, 4};
  v.extinction = 0.4f;
  v.fade = 1.0f;
  s.volumes.push_back(v);
  return s;
}

// The culling's definition, pixel by pixel: a tile needs the slices up to
// its farthest pixel (NaN skipped, none at or before the near plane); a
// column's active slices are the most its 3x3 tiles need, its lit slices the
// most its 3x3 columns' active slices reach (clamped at the edges).
void cull_by_definition(const FroxelGrid& g, const std::vector<float>& distance, std::vector<uint16_t>& active,
                        std::vector<uint16_t>& lit) {
  const int nx = g.nx(), ny = g.ny(), s = g.froxel_size();
  std::vector<uint16_t> needed(g.columns(), 0);
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      const float d = distance[size_t(y) * g.width() + x];
      if (!(d > g.near_distance())) continue;
      uint16_t& n = needed[size_t(y / s) * nx + x / s];
      n = std::max(n, uint16_t(g.slice_of(d) + 1));
    }
  const auto dilate = [&](const std::vector<uint16_t>& in) {
    std::vector<uint16_t> out(in.size(), 0);
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        for (int yy = std::max(y - 1, 0); yy <= std::min(y + 1, ny - 1); ++yy)
          for (int xx = std::max(x - 1, 0); xx <= std::min(x + 1, nx - 1); ++xx)
            out[size_t(y) * nx + x] = std::max(out[size_t(y) * nx + x], in[size_t(yy) * nx + xx]);
    return out;
  };
  active = dilate(needed);
  lit = dilate(active);
}

}  // namespace

TEST_CASE("depth culling matches its definition (partial tiles, sky, NaN, signed zeros, any thread count)") {
  const Camera cam = camera_at({0, 3, 10}, {1, 2, -10}, kCullW, kCullH);
  // Sizes that leave partial tiles on the right and bottom edges, and a single column of tiles.
  const int sizes[][3] = {{101, 45, 8}, {37, 29, 4}, {6, 21, 8}, {23, 1, 3}};
  std::mt19937 rng(7);
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const FroxelGrid grid(w, h, size[2], 24, 0.5f, 40.0f, 0.3f);
    std::vector<float> distance(size_t(w) * h);
    for (float& d : distance) {
      const float pick = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
      d = pick < 0.05f ? NAN : pick < 0.1f ? INFINITY : pick < 0.13f ? -0.0f : pick < 0.16f ? 0.0f
          : pick < 0.2f ? -3.0f : pick < 0.25f ? 60.0f : std::uniform_real_distribution<float>(0.0f, 12.0f)(rng);
    }
    // Regions of near surfaces, so the dilation has edges to spread.
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w / 3; ++x) distance[size_t(y) * w + x] = 0.25f + 0.01f * float(x);
    std::vector<uint16_t> active, lit;
    cull_by_definition(grid, distance, active, lit);
    for (unsigned threads : {1u, 3u}) {
      JobSystem jobs(threads);
      FroxelView view = make_froxel_view(grid, cam, jobs);
      cull_froxels_by_depth(view, distance, jobs);
      CHECK(view.active_slices == active);
      CHECK(view.lit_slices == lit);
    }
  }
}

TEST_CASE("depth culling skips hidden froxels and leaves the image bit-identical") {
  JobSystem jobs(2);
  FogProfileSettings p;
  p.froxel_size_px = 4;
  p.slices = 32;
  p.fog_distance = 48.0f;
  const Camera cam = camera_at({0, 3, 10}, {1, 2, -10}, kCullW, kCullH);
  const LightEnvironment l = light(kCullSun, 10000.0f, 50.0f);
  const ShadowMap shadow = wall_shadow(cam, kCullSun);
  const std::vector<float> distance = ground_distances();
  const FrameView view = frame_view(cam, cam, 0, false, kCullW, kCullH);
  FroxelFog culled(p, scene()), full(p, scene());
  const auto a = composite(culled, view, l, shadow, jobs, distance, glm::vec3(1.0f), true);
  const auto b = composite(full, view, l, shadow, jobs, distance, glm::vec3(1.0f), false);
  const size_t count = culled.grid().count();
  MESSAGE("active froxels " << culled.stats().active_froxels << ", lit " << culled.stats().lit_froxels << " of "
                            << count);
  CHECK(full.stats().lit_froxels == count);
  CHECK(culled.stats().active_froxels <= culled.stats().lit_froxels);
  CHECK(culled.stats().lit_froxels < count * 3 / 4);  // a real saving on this view
  REQUIRE(a.size() == b.size());
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0);
}

TEST_CASE("depth culling with history: culled froxels are never reprojected as history") {
  JobSystem jobs(2);
  FogProfileSettings p;
  p.slices = 32;
  p.fog_distance = 48.0f;
  const LightEnvironment l = light(kCullSun, 10000.0f, 50.0f);
  const std::vector<float> distance = ground_distances();
  FroxelFog culled(p, scene()), full(p, scene());
  Camera prev;
  double worst = 0.0;
  for (int f = 0; f < 10; ++f) {
    // The camera strafes, so history is read across the culled boundary.
    const glm::dvec3 pos(-2.0 + 0.4 * f, 3.0, 10.0);
    const Camera cam = camera_at(pos, pos + glm::dvec3(0.1, -0.05, -1.0), kCullW, kCullH);
    const ShadowMap shadow = wall_shadow(cam, kCullSun);
    const FrameView view = frame_view(cam, f ? prev : cam, f, f > 0, kCullW, kCullH);
    const auto a = composite(culled, view, l, shadow, jobs, distance, glm::vec3(1.0f), true);
    const auto b = composite(full, view, l, shadow, jobs, distance, glm::vec3(1.0f), false);
    for (const glm::vec3& c : a)
      for (int i = 0; i < 3; ++i) REQUIRE(std::isfinite(c[i]));
    worst = std::max(worst, mean_relative_error(b, a));
    prev = cam;
  }
  MESSAGE("worst mean relative difference culled vs full with history: " << worst);
  // Only history rejection at the culled boundary and the clamp's
  // neighbourhood differ; both are local.
  CHECK(worst < 0.01);
}

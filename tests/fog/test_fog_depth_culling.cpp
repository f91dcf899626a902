// Depth-aware culling: froxels behind the farthest surface of the pixels that
// can read them are skipped, and the image does not change.
#include <doctest/doctest.h>

#include <cstring>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kW = 96, kH = 64;
const glm::vec3 kSun(0.8f, 0.35f, 0.2f);

// Sky in the top quarter, "ground" below whose distance shrinks towards the
// bottom rows, and a near block (a wall 4 m away) on the left.
std::vector<float> ground_distances() {
  std::vector<float> d(size_t(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      float v = y < kH / 4 ? INFINITY : 2.0f + 24.0f * float(kH - y) / float(kH);
      if (x < 20 && y > 10) v = 4.0f;
      d[size_t(y) * kW + x] = v;
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

}  // namespace

TEST_CASE("depth culling skips hidden froxels and leaves the image bit-identical") {
  JobSystem jobs(2);
  FogProfileSettings p;
  p.froxel_size_px = 4;
  p.slices = 32;
  p.fog_distance = 48.0f;
  const Camera cam = camera_at({0, 3, 10}, {1, 2, -10}, kW, kH);
  const LightEnvironment l = light(kSun, 10000.0f, 50.0f);
  const ShadowMap shadow = wall_shadow(cam, kSun);
  const std::vector<float> distance = ground_distances();
  const FrameView view = frame_view(cam, cam, 0, false, kW, kH);
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
  const LightEnvironment l = light(kSun, 10000.0f, 50.0f);
  const std::vector<float> distance = ground_distances();
  FroxelFog culled(p, scene()), full(p, scene());
  Camera prev;
  double worst = 0.0;
  for (int f = 0; f < 10; ++f) {
    // The camera strafes, so history is read across the culled boundary.
    const glm::dvec3 pos(-2.0 + 0.4 * f, 3.0, 10.0);
    const Camera cam = camera_at(pos, pos + glm::dvec3(0.1, -0.05, -1.0), kW, kH);
    const ShadowMap shadow = wall_shadow(cam, kSun);
    const FrameView view = frame_view(cam, f ? prev : cam, f, f > 0, kW, kH);
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

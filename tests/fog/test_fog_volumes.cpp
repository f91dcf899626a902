#include <doctest/doctest.h>

#include <cstring>

#include "fog/fog_medium.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

FogVolume box(glm::dvec3 c, glm::vec3 half, float ext, FogBlend b, glm::vec3 albedo = glm::vec3(1.0f)) {
  FogVolume v;
  v.center = c;
  v.half_size = half;
  v.extinction = ext;
  v.blend = b;
  v.albedo = albedo;
  return v;
}

}  // namespace

TEST_CASE("blend modes apply in file order over the height fog") {
  FogSceneSettings s = uniform_fog(0.1f, glm::vec3(0.5f));
  s.volumes = {box({0, 0, 0}, {1, 1, 1}, 0.4f, FogBlend::Additive),
               box({0, 0, 0}, {1, 1, 1}, 0.25f, FogBlend::Max),
               box({0, 0, 0}, {1, 1, 1}, 2.0f, FogBlend::Multiply, glm::vec3(0.5f)),
               box({0, 0, 0}, {1, 1, 1}, 0.8f, FogBlend::Min)};
  FogMedium m(s);
  m.set_camera({0, 0, 10});
  const glm::vec3 inside(0, 0, -10), outside(5, 0, -10);
  CHECK(m.sample(outside).extinction == doctest::Approx(0.1f));
  // 0.1 + 0.4 = 0.5; max(0.5, 0.25) = 0.5; x 2 = 1.0; min(1.0, 0.8) = 0.8.
  const FogDensity d = m.sample(inside);
  CHECK(d.extinction == doctest::Approx(0.8f));
  // Scattering: 0.05 + 0.4 = 0.45; max 0.45; x (0.5 * 2) = 0.45; min(0.45, 0.8) = 0.45.
  CHECK(d.scattering.x == doctest::Approx(0.45f));
  // Overwrite replaces; order matters.
  s.volumes = {box({0, 0, 0}, {1, 1, 1}, 0.3f, FogBlend::Overwrite), box({0, 0, 0}, {1, 1, 1}, 0.2f, FogBlend::Additive)};
  FogMedium o(s);
  o.set_camera({0, 0, 10});
  CHECK(o.sample(inside).extinction == doctest::Approx(0.5f));
}

TEST_CASE("edge fade ramps the volume in from its faces") {
  FogSceneSettings s;
  FogVolume v = box({0, 0, 0}, {2, 2, 2}, 1.0f, FogBlend::Additive);
  v.fade = 1.0f;
  s.volumes = {v};
  FogMedium m(s);
  m.set_camera({0, 0, 0});
  CHECK(m.sample({0, 0, 0}).extinction == doctest::Approx(1.0f));
  CHECK(m.sample({1.5f, 0, 0}).extinction == doctest::Approx(0.5f));
  CHECK(m.sample({0, -1.9f, 0}).extinction == doctest::Approx(0.1f));
  CHECK(m.sample({2.1f, 0, 0}).extinction == 0.0f);
}

TEST_CASE("procedural noise modulates density within [1 - strength, 1]") {
  FogSceneSettings s;
  FogVolume v = box({0, 0, 0}, {10, 10, 10}, 1.0f, FogBlend::Additive);
  v.noise.enabled = true;
  v.noise.strength = 0.6f;
  s.volumes = {v};
  FogMedium m(s);
  m.set_camera({0, 0, 0});
  float lo = 1.0f, hi = 0.0f;
  for (int i = 0; i < 500; ++i) {
    const float e = m.sample(glm::vec3(float(i % 17) * 0.53f - 4.0f, float(i % 7) - 3.0f, float(i) * 0.017f - 4.0f)).extinction;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  CHECK(lo >= 0.4f);
  CHECK(hi <= 1.0f);
  CHECK(hi - lo > 0.2f);  // it does vary
}

TEST_CASE("volumes outside the view cost nothing and only overlapped froxels change") {
  JobSystem jobs(2);
  const int w = 64, h = 48;
  const Camera cam = camera_at({0, 2, 0}, {0, 2, -10}, w, h);
  FogProfileSettings p;
  p.slices = 32;
  const FroxelGrid grid(w, h, p.froxel_size_px, p.slices, cam.znear, p.fog_distance, p.slice_uniformity);
  const FroxelView view = make_froxel_view(grid, cam, jobs);

  FogSceneSettings base = uniform_fog(0.02f, glm::vec3(1.0f));
  FogSceneSettings hidden = base;
  hidden.volumes = {box({0, 2, 30}, {3, 3, 3}, 1.0f, FogBlend::Additive),      // behind the camera
                    box({200, 2, -20}, {3, 3, 3}, 1.0f, FogBlend::Additive),   // far to the side
                    box({0, 2, -500}, {3, 3, 3}, 1.0f, FogBlend::Additive)};   // beyond the fog range
  FogMedium m0(base), m1(hidden);
  m0.set_camera(cam.position);
  m1.set_camera(cam.position);
  std::vector<FogDensity> d0, d1;
  voxelize_density(view, m0, 1, jobs, d0);
  const VoxelizeStats st = voxelize_density(view, m1, 1, jobs, d1);
  CHECK(st.visible_volumes == 0);
  CHECK(st.volume_froxels == 0);
  for (size_t i = 0; i < d0.size(); ++i) CHECK(d0[i].extinction == d1[i].extinction);

  FogSceneSettings one = base;
  one.volumes = {box({3, 2, -12}, {1.5f, 1.5f, 1.5f}, 1.0f, FogBlend::Additive)};
  FogMedium m2(one);
  m2.set_camera(cam.position);
  std::vector<FogDensity> d2;
  const VoxelizeStats s2 = voxelize_density(view, m2, 1, jobs, d2);
  REQUIRE(s2.visible_volumes == 1);
  CHECK(s2.volume_froxels < grid.count() / 20);  // a small box touches a small footprint
  const VolumeFootprint f = volume_footprints(view, m2)[0];
  size_t changed = 0;
  for (int y = 0; y < grid.ny(); ++y)
    for (int x = 0; x < grid.nx(); ++x)
      for (int k = 0; k < grid.nz(); ++k) {
        const size_t i = grid.index(x, y, k);
        if (d2[i].extinction == d0[i].extinction) continue;
        ++changed;
        CHECK((x >= f.x0 && x <= f.x1 && y >= f.y0 && y <= f.y1 && k >= f.k0 && k <= f.k1));
        // The changed froxel's centre is inside the box.
        const glm::vec3 c = view.directions[size_t(y) * grid.nx() + x] * grid.center(k) + glm::vec3(cam.position);
        CHECK(std::abs(c.x - 3.0f) <= 1.5f);
        CHECK(std::abs(c.z + 12.0f) <= 1.5f);
      }
  CHECK(changed > 0);
}

namespace {

// Volumes around a camera at (0, 2, 0) looking down -z (60 degrees, 4:3):
// a rotated one with noise and fade in view, one holding the camera (across
// the near plane), one reaching from the view to behind the camera on the
// right, one beside the camera and out of view, one far ahead.
FogSceneSettings volumes_around_the_camera() {
  FogSceneSettings s = uniform_fog(0.03f, glm::vec3(0.9f));
  s.base_height = 0.0f;  // a height fog that varies inside a froxel
  s.max_height = 20.0f;
  FogVolume rotated = box({2, 1, -12}, {2, 1.5f, 3}, 0.6f, FogBlend::Max, glm::vec3(0.7f));
  const float c = std::cos(0.5f), sn = std::sin(0.5f);
  rotated.axes[0] = {c, 0, -sn};
  rotated.axes[2] = {sn, 0, c};
  rotated.fade = 0.5f;
  rotated.noise.enabled = true;
  rotated.noise.strength = 0.5f;
  FogVolume around = box({0, 2, 1}, {1, 1, 1.5f}, 0.4f, FogBlend::Additive);
  around.fade = 0.3f;
  s.volumes = {rotated, around, box({3, 2, 0}, {1, 1, 3}, 0.2f, FogBlend::Overwrite),
               box({5, 2, 0.5}, {1, 1, 1}, 3.0f, FogBlend::Multiply), box({-4, 3, -60}, {5, 5, 5}, 0.01f, FogBlend::Min)};
  return s;
}

// That medium seen from the camera, on a 64x48 grid of 32 slices.
struct AroundTheCamera {
  JobSystem jobs{2};
  Camera cam = camera_at({0, 2, 0}, {0, 2, -10}, 64, 48);
  FroxelGrid grid{64, 48, 8, 32, cam.znear, 64.0f, 0.5f};
  FroxelView view = make_froxel_view(grid, cam, jobs);
  FogMedium m{volumes_around_the_camera()};
  AroundTheCamera() { m.set_camera(cam.position); }
};

}  // namespace

TEST_CASE("footprints only bound the work: the density is the same as with every volume over the whole grid") {
  AroundTheCamera c;
  const FroxelGrid& grid = c.grid;
  const FroxelView& view = c.view;
  const FogMedium& m = c.m;
  for (int samples : {1, 4}) {
    CAPTURE(samples);
    const DensityPlan plan = plan_density(view, m, samples);
    DensityPlan everywhere = plan;
    everywhere.footprints.clear();
    for (size_t i = 0; i < m.volumes().size(); ++i)
      everywhere.footprints.push_back(
          VolumeFootprint{int(i), 0, 0, grid.nx() - 1, grid.ny() - 1, 0, grid.nz() - 1});
    std::vector<FogDensity> bounded(grid.count()), full(grid.count());
    voxelize_rows(view, m, plan, 0, grid.ny(), bounded);
    voxelize_rows(view, m, everywhere, 0, grid.ny(), full);
    CHECK(std::memcmp(bounded.data(), full.data(), bounded.size() * sizeof(FogDensity)) == 0);
    // And the volumes do change the field (the test is not vacuous).
    FogSceneSettings fog_only = volumes_around_the_camera();
    fog_only.volumes.clear();
    FogMedium height_only(fog_only);
    height_only.set_camera(c.cam.position);
    std::vector<FogDensity> none(grid.count());
    voxelize_rows(view, height_only, plan_density(view, height_only, samples), 0, grid.ny(), none);
    size_t changed = 0;
    for (size_t i = 0; i < none.size(); ++i) changed += none[i].extinction != bounded[i].extinction;
    CHECK(changed > grid.count() / 50);
    CHECK(changed < grid.count() / 2);
  }
}

TEST_CASE("a volume reaching behind the camera has a bounded footprint; one beside the camera has none") {
  AroundTheCamera c;
  const FroxelGrid& grid = c.grid;
  const std::vector<VolumeFootprint> f = volume_footprints(c.view, c.m);
  std::vector<int> of(c.m.volumes().size(), -1);
  for (size_t i = 0; i < f.size(); ++i) of[size_t(f[i].volume)] = int(i);
  REQUIRE(of[2] >= 0);
  REQUIRE(of[1] >= 0);
  // The box on the right (x from 2 to 4, z from -3 to 3) is seen only in the
  // screen's right half.
  CHECK(f[size_t(of[2])].x0 >= grid.nx() / 2);
  CHECK(f[size_t(of[2])].x1 == grid.nx() - 1);
  // The box holding the camera covers the screen, in its first slices only.
  CHECK(f[size_t(of[1])].x0 == 0);
  CHECK(f[size_t(of[1])].x1 == grid.nx() - 1);
  CHECK(f[size_t(of[1])].k1 < grid.nz() / 2);
  // Beside the camera (x from 4 to 6, z from -0.5 to 1.5): out of view.
  CHECK(of[3] == -1);
  CHECK(of[0] >= 0);
  CHECK(of[4] >= 0);
}

TEST_CASE("where volumes lie, a froxel takes the slice's mean density (its exact optical depth)") {
  JobSystem jobs(2);
  const int w = 160, h = 96;
  const Camera cam = camera_at({0, 2, 0}, {0, 2, -10}, w, h);
  FogProfileSettings p;
  p.slices = 16;
  const FroxelGrid grid(w, h, p.froxel_size_px, p.slices, cam.znear, p.fog_distance, p.slice_uniformity);
  const FroxelView view = make_froxel_view(grid, cam, jobs);
  // A sharp-edged slab across the view whose near face (z = -face) cuts the
  // middle of slice k along the centre column's ray.
  const int x = grid.nx() / 2, y = grid.ny() / 2, k = 10;
  const glm::vec3 dir = view.directions[size_t(y) * grid.nx() + x];
  const float t_cut = grid.boundary(k) + 0.37f * grid.thickness(k);
  const float face = -dir.z * t_cut;
  const float ext = 0.5f;
  FogSceneSettings s;
  s.volumes = {box({0, 2, -(face + 50.0)}, {100, 100, 50}, ext, FogBlend::Additive)};
  FogMedium m(s);
  m.set_camera(cam.position);
  const size_t i = grid.index(x, y, k);
  std::vector<FogDensity> point, mean;
  voxelize_density(view, m, 1, jobs, point);
  voxelize_density(view, m, 64, jobs, mean);
  // Covered fraction of the slice: from the cut to the far boundary.
  const float covered = (grid.boundary(k + 1) - t_cut) / grid.thickness(k);
  CHECK(mean[i].extinction == doctest::Approx(ext * covered).epsilon(1.0 / 64.0 / covered));
  CHECK(mean[i].scattering.x == doctest::Approx(mean[i].extinction));
  // One point (the slice centre) sees all or nothing.
  CHECK((point[i].extinction == 0.0f || point[i].extinction == ext));
  // Slices wholly in front of or behind the face are unchanged by averaging.
  CHECK(mean[grid.index(x, y, k - 1)].extinction == 0.0f);
  CHECK(mean[grid.index(x, y, k + 1)].extinction == doctest::Approx(ext));
}

TEST_CASE("volume shadow lookup agrees with ShadowMap::visibility without PCF") {
  const Camera cam = camera_at({0, 2, 20}, {0, 2, 0}, 64, 48);
  const glm::vec3 sun(0.7f, 0.5f, 0.1f);
  ShadowMap m = wall_shadow(cam, sun);
  m.pcf_radius = 0;
  const VolumeShadow vs(m, cam.position);
  int lit = 0, shadowed = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::vec3 dir = glm::normalize(glm::vec3(float(i % 20) * 0.05f - 0.5f, float(i / 20) * 0.02f - 0.2f, -1.0f));
    const VolumeShadow::Ray r = vs.ray(glm::vec3(0.0f), dir);
    for (float t : {5.0f, 12.0f, 19.0f, 23.0f, 30.0f, 45.0f}) {
      const float a = vs.visibility(r, t);
      const float b = m.visibility(glm::vec3(cam.position) + dir * t, glm::vec3(0.0f));
      CHECK(a == doctest::Approx(b).epsilon(1e-3));
      lit += a > 0.99f;
      shadowed += a < 0.01f;
    }
  }
  CHECK(lit > 100);
  CHECK(shadowed > 100);
}

TEST_CASE("froxel view: column directions are PixelRays' bits at the column centres, for any thread count") {
  const int sizes[][3] = {{1280, 720, 8}, {101, 45, 8}, {37, 29, 4}, {6, 21, 8}};
  const glm::dvec3 targets[] = {{1, 2, -10}, {-30, -8, 4}, {0.2, 40, 0.1}, {5, 3.1, 10.5}};
  for (const auto& size : sizes)
    for (const glm::dvec3& target : targets) {
      const int w = size[0], h = size[1];
      const Camera cam = camera_at({0, 3, 10}, target, w, h, 35.0f + float(w % 50));
      const FroxelGrid grid(w, h, size[2], 16, cam.znear, 40.0f, 0.3f);
      const PixelRays rays(cam, w, h);
      for (unsigned threads : {1u, 3u}) {
        JobSystem jobs(threads);
        const FroxelView view = make_froxel_view(grid, cam, jobs);
        size_t mismatched = 0;
        for (int y = 0; y < grid.ny(); ++y)
          for (int x = 0; x < grid.nx(); ++x) {
            const glm::vec2 p = grid.column_center_px(x, y);
            const glm::vec3 d = rays.direction(p.x, p.y), got = view.directions[size_t(y) * grid.nx() + x];
            mismatched += std::memcmp(&d, &got, sizeof(d)) != 0;
          }
        CHECK(mismatched == 0);
        CHECK(view.active_slices == std::vector<uint16_t>(grid.columns(), uint16_t(grid.nz())));
        CHECK(view.lit_slices == view.active_slices);
      }
    }
}

#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "fog/fog_medium.h"
#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/jitter_sequence.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

// The column fast paths against their one-point definitions, same bits.

// Height fog along rays that start below the base, cross the layer and end
// above the cutoff (clear air), with counts that leave every tail length.
TEST_CASE("height_fog_column gives the bits of height_fog") {
  FogSceneSettings s = uniform_fog(0.05f, glm::vec3(0.9f, 0.7f, 0.4f));
  s.base_height = 2.0f;
  s.max_height = 6.0f;
  FogMedium m(s);
  m.set_camera({0.0, 3.0, 0.0});
  size_t below = 0, clear = 0, graded = 0;
  for (int r = 0; r < 24; ++r) {
    const float a = -0.6f + 0.07f * float(r);
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, a, -1.0f));
    const int n = 1 + r * 5 % 64;
    std::vector<float> t(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) t[size_t(k)] = 0.1f + 80.0f * float(k * k) / float(64 * 64);
    std::vector<FogDensity> column(static_cast<size_t>(n));
    m.height_fog_column(dir, t.data(), n, column.data());
    for (int k = 0; k < n; ++k) {
      const FogDensity d = m.height_fog(dir * t[size_t(k)]);
      CHECK(std::memcmp(&d, &column[size_t(k)], sizeof(FogDensity)) == 0);
      below += d.extinction == s.extinction;
      clear += d.extinction == 0.0f;
      graded += d.extinction > 0.0f && d.extinction < s.extinction;
    }
  }
  CHECK(below > 0);
  CHECK(clear > 0);
  CHECK(graded > 0);
}

// light_froxels against the per-froxel definition: clear air 0, else the
// one-point shadow lookup at the importance-sampled jittered point. The
// density has clear air before, after and between scattering slices, and
// optically thick slices (the log form).
TEST_CASE("light_froxels gives the bits of the per-froxel definition") {
  const int w = 64, h = 40;
  const Camera cam = camera_at({-3, 2, 10}, {0, 2, -10}, w, h);
  const glm::vec3 sun(0.6f, 0.4f, 0.3f);
  const ShadowMap map = wall_shadow(cam, sun);
  const VolumeShadow shadow(map, cam.position);
  JobSystem jobs(2);
  const FroxelGrid grid(w, h, 8, 40, 0.1f, 60.0f, 0.5f);
  FroxelView view = make_froxel_view(grid, cam, jobs);
  for (size_t c = 0; c < grid.columns(); ++c) view.lit_slices[c] = uint16_t(c * 7 % 41);
  std::vector<FogDensity> density(grid.count());
  for (size_t i = 0; i < density.size(); ++i) {
    const int k = int(i % size_t(grid.nz()));
    const size_t c = i / size_t(grid.nz());
    const bool scatters = k >= int(c % 5) && k < grid.nz() - int(c % 9) && (k + int(c)) % 11 != 0;
    const float extinction = (k + int(c)) % 13 == 0 ? 0.5f : 0.01f + 0.001f * float(k);
    if (scatters) density[i] = FogDensity{glm::vec3(0.8f * extinction), extinction};
  }
  // Last frame's map under a sun 4 degrees round: the light change per sample.
  const ShadowMap moved_map = wall_shadow(cam, glm::normalize(glm::vec3(0.62f, 0.4f, 0.26f)));
  const VolumeShadow moved(moved_map, cam.position);
  for (int samples : {1, 3}) {
    JitterInputs jitter;
    jitter.frame = 4;
    jitter.samples = samples;
    std::vector<float> sun_visibility, with_change, change;
    light_froxels(view, density, shadow, jitter, jobs, sun_visibility);
    light_froxels(view, density, shadow, jitter, jobs, with_change, nullptr, &moved, &change);
    CHECK(with_change == sun_visibility);  // measuring the change does not touch the visibility
    size_t mismatches = 0, shadowed = 0, partial = 0, changed = 0;
    for (int y = 0; y < grid.ny(); ++y)
      for (int x = 0; x < grid.nx(); ++x) {
        const glm::vec2 px = grid.column_center_px(x, y);
        for (int k = 0; k < view.lit_slices[size_t(y) * grid.nx() + x]; ++k) {
          const FogDensity& d = density[grid.index(x, y, k)];
          float sum = 0.0f, delta = 0.0f;
          for (int i = 0; i < samples; ++i) {
            const FroxelJitter j = froxel_jitter(jitter.frame + i);
            const float u = std::fmod(column_hash(x, y) + j.depth, 1.0f);
            const float s = float(grid.froxel_size());
            const glm::vec3 dir = cam.ray_direction(px.x + j.lateral.x * s, px.y + j.lateral.y * s, w, h);
            const float t = grid.boundary(k) +
                            importance_sample_offset(u, std::max(d.extinction, 1e-12f), grid.thickness(k));
            const bool clear = d.scattering == glm::vec3(0.0f);
            const float now = shadow.visibility(shadow.ray(glm::vec3(0.0f), dir), t);
            const float then = moved.visibility(moved.ray(glm::vec3(0.0f), dir), t);
            sum += clear ? 0.0f : now;
            delta += clear ? 0.0f : std::abs(now - then);
          }
          if (samples > 1) {
            sum /= float(samples);
            delta /= float(samples);
          }
          const float got = sun_visibility[grid.index(x, y, k)];
          const float got_change = change[grid.index(x, y, k)];
          mismatches += std::memcmp(&got, &sum, sizeof(float)) != 0;
          mismatches += std::memcmp(&got_change, &delta, sizeof(float)) != 0;
          changed += got_change > 0.0f;
          shadowed += got == 0.0f && d.scattering != glm::vec3(0.0f);
          partial += got > 0.0f && got < 1.0f;
        }
      }
    CHECK(mismatches == 0);
    CHECK(shadowed > 0);
    CHECK(partial > 0);
    CHECK(changed > 0);
  }
}

// The batched lookup at the map's border, where some of a point's 2x2 taps
// are off the map (lit) and the rest on it: an opaque map, so every on-map
// tap is shadowed and any tap read from the wrong texel changes the result.
TEST_CASE("batched shadow lookups match single lookups across the map's border") {
  const Camera cam = camera_at({-3, 2, 10}, {0, 2, -10}, 160, 90);
  ShadowMap map = wall_shadow(cam, glm::vec3(0.6f, 0.4f, 0.3f));
  std::fill(map.depth.begin(), map.depth.end(), 2.0f);  // beyond every receiver: occluded
  const VolumeShadow shadow(map, cam.position);
  const float s = float(map.size);
  std::vector<float> t(77), batch(t.size()), single(t.size());
  for (size_t k = 0; k < t.size(); ++k) t[k] = float(k) / float(t.size() - 1);
  size_t partial = 0;
  for (float across : {-0.7f, -0.2f, 0.3f, 0.9f, s - 1.6f, s - 1.2f, s - 0.6f, s - 0.1f}) {
    for (int axis = 0; axis < 2; ++axis) {
      // Along one texel axis from just outside the map (-1.5) to just past it (s + 0.5).
      VolumeShadow::Ray ray;
      ray.origin = axis == 0 ? glm::vec3(-1.5f, across, 0.5f) : glm::vec3(across, -1.5f, 0.5f);
      ray.step = axis == 0 ? glm::vec3(s + 2.0f, 0.0f, 0.0f) : glm::vec3(0.0f, s + 2.0f, 0.0f);
      for (int start : {0, 3}) {
        const float* tk = t.data() + start;
        const int n = int(t.size()) - start;
        shadow.visibility(ray, tk, n, batch.data());
        for (int k = 0; k < n; ++k) {
          single[size_t(k)] = shadow.visibility(ray, tk[k]);
          partial += single[size_t(k)] > 0.0f && single[size_t(k)] < 1.0f;
        }
        CHECK(std::memcmp(batch.data(), single.data(), size_t(n) * sizeof(float)) == 0);
      }
    }
  }
  CHECK(partial > 0);
}

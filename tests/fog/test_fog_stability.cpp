// Stability sweep: no NaN/Inf and physically bounded output over extinction
// 0 .. 1000 /m (the shortest mean free path a scene may give, 1 mm), anisotropy -0.99 .. 0.99, both phase functions,
// the camera inside a volume, volumes crossing the near plane, zero-size
// volumes and camera cuts. Each runs at both precisions (profile
// "precision"): the fixed-point volume is checked as it decodes, and its
// codes for wrap-around.
#include <doctest/doctest.h>

#include <cmath>

#include "fog/phase_function.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kStabilityW = 40, kStabilityH = 24;
constexpr float kSunLux = 1e5f, kAmbient = 1e3f;
constexpr FogPrecision kPrecisions[] = {FogPrecision::Float, FogPrecision::Fixed};

// L <= (max phase * E + La) (1 - T) for albedo <= 1 (energy conservation),
// over every froxel the frame produced (the active slices of each column);
// along a column T never rises and L never falls. The fixed-point volume's
// radiance is hdr16 (relative step 2^-11) and its T rounds the depth to
// 2^-11 log2 units (relative 1.7e-4): the bound allows for both.
void check_bounded(const FroxelFog& fog, FogPhase phase, float g, float sun_lux = kSunLux) {
  const float p_max = std::max(evaluate_phase(phase, 1.0f, g), evaluate_phase(phase, -1.0f, g));
  const bool fixed = fog.fixed_point();
  const float bound = (p_max * sun_lux + kAmbient) * (fixed ? 1.0006f : 1.0001f) + 1e-3f;
  const float t_slack = fixed ? 2e-4f : 0.0f;
  const FroxelGrid& grid = fog.grid();
  for (size_t column = 0; column < grid.columns(); ++column) {
    IntegratedFroxel before;  // the near plane
    for (int k = 0; k < fog.view().active_slices[column]; ++k) {
      const size_t i = column * size_t(grid.nz()) + size_t(k);
      const IntegratedFroxel f = fog.integrated_froxel(i);
      REQUIRE(std::isfinite(f.transmittance));
      REQUIRE(f.transmittance >= 0.0f);
      REQUIRE(f.transmittance <= before.transmittance);
      for (int c = 0; c < 3; ++c) {
        REQUIRE(std::isfinite(f.in_scatter[c]));
        REQUIRE(f.in_scatter[c] >= before.in_scatter[c]);
        REQUIRE(f.in_scatter[c] <= bound * (1.0f - f.transmittance + t_slack) + 1e-3f);
      }
      if (fixed && k > 0) {
        // The codes themselves never decrease: a wrap-around would.
        const FixedIntegratedFroxel &now = fog.fixed_volume()[i], &last = fog.fixed_volume()[i - 1];
        REQUIRE(now.optical_depth >= last.optical_depth);
        for (int c = 0; c < 3; ++c) REQUIRE(now.in_scatter[c] >= last.in_scatter[c]);
      }
      before = f;
    }
  }
}

void check_image(const std::vector<glm::vec3>& img) {
  for (const glm::vec3& c : img)
    for (int i = 0; i < 3; ++i) {
      REQUIRE(std::isfinite(c[i]));
      REQUIRE(c[i] >= 0.0f);
    }
}

std::vector<float> mixed_distances() {
  std::vector<float> d(size_t(kStabilityW) * kStabilityH);
  const float values[] = {0.0f, 0.01f, 0.1f, 0.5f, 3.0f, 30.0f, 1e4f, INFINITY, NAN};
  for (size_t i = 0; i < d.size(); ++i) d[i] = values[i % 9];
  return d;
}

}  // namespace

TEST_CASE("stability sweep: extinction, anisotropy and phase") {
  JobSystem jobs(2);
  const Camera cam = camera_at({0, 2, 5}, {0, 2, -10}, kStabilityW, kStabilityH);
  const glm::vec3 sun(0.2f, 0.5f, -0.8f);  // looking almost into the sun: the phase peak
  const ShadowMap shadow = wall_shadow(cam, sun);
  // 1e-30 and 1000 /m: the extinctions of the longest and shortest mean free
  // paths a scene may give (1e30 m and 1 mm).
  for (FogPrecision precision : kPrecisions)
    for (float extinction : {0.0f, 1e-30f, 1e-4f, 0.02f, 1.0f, 10.0f, 1000.0f})
      for (float g : {-0.99f, -0.5f, 0.0f, 0.7f, 0.99f})
        for (FogPhase phase : {FogPhase::HenyeyGreenstein, FogPhase::CornetteShanks}) {
          CAPTURE(precision);
          CAPTURE(extinction);
          CAPTURE(g);
          FogSceneSettings s = uniform_fog(extinction, glm::vec3(1.0f), g);
          s.phase = phase;
          FogProfileSettings p;
          p.slices = 16;
          p.precision = precision;
          FroxelFog fog(p, s);
          Camera prev = cam;
          for (int f = 0; f < 2; ++f) {
            const auto img = composite(fog, frame_view(cam, prev, f, f > 0, kStabilityW, kStabilityH), light(sun, kSunLux, kAmbient), shadow,
                                       jobs, mixed_distances(), glm::vec3(1.0f));
            check_image(img);
            check_bounded(fog, phase, g);
          }
        }
}

TEST_CASE("stability: camera inside volumes, volumes crossing the near plane, zero-size volumes, cuts") {
  JobSystem jobs(2);
  FogSceneSettings s;
  s.anisotropy = 0.9f;
  auto add = [&](glm::dvec3 c, glm::vec3 half, float ext, FogBlend b, float fade, bool noise) {
    FogVolume v;
    v.center = c;
    v.half_size = half;
    v.extinction = ext;
    v.blend = b;
    v.fade = fade;
    v.noise.enabled = noise;
    s.volumes.push_back(v);
  };
  add({0, 2, 5}, {3, 3, 3}, 10.0f, FogBlend::Overwrite, 0.5f, true);           // contains the camera
  add({0, 2, 4.9}, {5, 5, 0.08f}, 10.0f, FogBlend::Additive, 0.0f, false);    // thin sheet across the near plane
  add({0, 2, 5}, {0, 0, 0}, 10.0f, FogBlend::Max, 1.0f, false);               // zero size
  add({0, 2, 0}, {0, 1, 1}, 10.0f, FogBlend::Additive, 0.0f, false);          // zero along one axis
  add({0, 2, -5}, {2, 2, 2}, 0.5f, FogBlend::Multiply, 1.0f, true);
  add({0, 2, -8}, {4, 4, 4}, 0.01f, FogBlend::Min, 2.0f, false);
  add({0, 2, 50}, {2, 2, 2}, 10.0f, FogBlend::Additive, 0.0f, false);         // behind the camera
  for (FogPrecision precision : kPrecisions) {
    CAPTURE(precision);
    FogProfileSettings p;
    p.slices = 16;
    p.precision = precision;
    FroxelFog fog(p, s);
    const glm::vec3 sun(0.3f, 0.6f, -0.5f);
    Camera prev;
    for (int f = 0; f < 6; ++f) {
      // Frames 0-2 inside the first volume; frame 3 cuts far away; 4-5 move fast.
      const glm::dvec3 pos = f < 3 ? glm::dvec3(0.1 * f, 2, 5) : glm::dvec3(40.0 * f, 30, 80);
      const Camera cam = camera_at(pos, pos + glm::dvec3(0.1, -0.05, -1), kStabilityW, kStabilityH);
      const bool cut = f == 0 || f == 3;
      const auto img = composite(fog, frame_view(cam, cut ? cam : prev, f, !cut, kStabilityW, kStabilityH), light(sun, kSunLux, kAmbient),
                                 wall_shadow(cam, sun), jobs, mixed_distances(), glm::vec3(0.5f));
      check_image(img);
      check_bounded(fog, FogPhase::HenyeyGreenstein, 0.9f);
      // Seen: the volume holding the camera, the sheet, the two ahead.
      if (f < 3) CHECK(fog.stats().voxelize.visible_volumes == 4);
      prev = cam;
    }
  }
}

TEST_CASE("stability: a long still view, then a sun that jumps every frame") {
  JobSystem jobs(2);
  const Camera cam = camera_at({0, 2, 5}, {0, 2, -10}, kStabilityW, kStabilityH);
  for (FogPrecision precision : kPrecisions)
    for (float extinction : {1e-4f, 10.0f}) {
      CAPTURE(precision);
      CAPTURE(extinction);
      FogProfileSettings p;
      p.slices = 16;
      p.precision = precision;
      FroxelFog fog(p, uniform_fog(extinction, glm::vec3(1.0f), 0.99f));
      ShadowMap previous;
      for (int f = 0; f < 24; ++f) {
        // Still for 16 frames (the running mean's weight climbs to 16/17),
        // then the sun jumps 40 degrees a frame, through the camera's view.
        const float a = glm::radians(f < 16 ? 10.0f : 10.0f + 40.0f * float(f - 15));
        const glm::vec3 sun = glm::normalize(glm::vec3(std::sin(a), 0.4f, -std::cos(a)));
        const ShadowMap shadow = wall_shadow(cam, sun);
        const auto img = composite(fog, frame_view(cam, cam, f, f > 0, kStabilityW, kStabilityH), light(sun, kSunLux, kAmbient), shadow,
                                   jobs, mixed_distances(), glm::vec3(1.0f), true, &previous);
        check_image(img);
        check_bounded(fog, FogPhase::HenyeyGreenstein, 0.99f);
        CHECK(fog.stats().still_frames == (f < 16 ? f : 0));
        CHECK(fog.stats().light_changed == (f >= 16));
        previous = shadow;
      }
    }
}

// Where fixed point runs out of range: fog with a mean free path of 0.1 m
// (the transmittance's depth saturates within metres), columns of 1024
// slices over 10 km (thin slices, long sums) and a sun bright enough that
// the in-scatter passes hdr16's top (8.6e9). Both precisions stay finite,
// bounded and monotone; the fixed-point codes saturate at their top instead
// of wrapping, and stay there along the column.
TEST_CASE("stability: dense fog, long columns and a sun past hdr16's range, at both precisions") {
  JobSystem jobs(2);
  const Camera cam = camera_at({0, 2, 5}, {0, 2, -10}, kStabilityW, kStabilityH);
  const glm::vec3 sun(0.2f, 0.5f, -0.8f);
  const ShadowMap shadow = wall_shadow(cam, sun);
  struct Case {
    const char* name;
    float extinction, sun_lux, fog_distance;
    int slices;
  };
  const Case cases[] = {{"dense", 10.0f, kSunLux, 64.0f, 64},
                        {"long columns", 0.02f, kSunLux, 1e4f, 1024},
                        {"dense long columns", 10.0f, kSunLux, 1e4f, 1024},
                        {"bright sun", 0.02f, 1e12f, 64.0f, 64}};
  for (const Case& c : cases)
    for (FogPrecision precision : kPrecisions) {
      CAPTURE(c.name);
      CAPTURE(precision);
      FogProfileSettings p;
      p.slices = c.slices;
      p.fog_distance = c.fog_distance;
      p.precision = precision;
      FroxelFog fog(p, uniform_fog(c.extinction, glm::vec3(1.0f), 0.99f));
      for (int f = 0; f < 2; ++f) {
        const auto img = composite(fog, frame_view(cam, cam, f, f > 0, kStabilityW, kStabilityH), light(sun, c.sun_lux, kAmbient),
                                   shadow, jobs, mixed_distances(), glm::vec3(1.0f));
        check_image(img);
        check_bounded(fog, FogPhase::HenyeyGreenstein, 0.99f, c.sun_lux);
      }
      if (!fog.fixed_point()) continue;
      // The edge was reached: dense fog saturates the depth code (the
      // transmittance is 0 there), the bright sun the radiance codes.
      size_t depth_top = 0, radiance_top = 0;
      for (const FixedIntegratedFroxel& f : fog.fixed_volume()) {
        depth_top += f.optical_depth == 0xFFFF;
        radiance_top += f.in_scatter[0] == 0xFFFF;
      }
      if (c.extinction >= 10.0f) {
        CHECK(depth_top > 0);
        CHECK(transmittance_q15(0xFFFF) == 0);
      }
      if (c.sun_lux > kSunLux) {
        CHECK(radiance_top > 0);
        CHECK(fx::decode_hdr16(0xFFFF) == fx::kHdr16Max);
      }
    }
}

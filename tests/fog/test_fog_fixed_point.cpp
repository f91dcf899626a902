// The fixed-point fog ("precision": "fixed") against the float fog on the
// shipped fog scenes' settings, and its arithmetic at the edges of its
// ranges: sums and codes that would wrap around saturate instead. The
// stability sweeps and the thread-count test run both precisions
// (test_fog_stability.cpp, test_fog_determinism.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "engine/output/percentile.h"
#include "fog/sun_term_format.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

FogSceneSettings scene_fog(const std::string& name) {
  const std::string path = std::string(CR_SOURCE_DIR) + "/scenes/" + name;
  std::ifstream in(path);
  REQUIRE(in.good());
  return parse_fog_scene(nlohmann::json::parse(in).at("fog"), path);
}

}  // namespace

// Each shipped fog scene's fog (density, phase, distance) under a low sun in
// front of the camera (the phase peak), with a wall's shaft, over surfaces
// from 2 m to 100 m and sky: a moving camera for 6 frames, then a still view
// for 12 (its jitter mean). Every pixel's relative luminance difference
// between the two precisions, over all frames: measured mean 0.9e-4 / p95
// 2.5e-4 / largest 7.2e-4 (valley) and 1.0e-4 / 2.6e-4 / 1.0e-3 (volumes).
TEST_CASE("fixed point against float on the shipped fog scenes' settings: within 3e-4 mean, 1e-3 p95, 4e-3 worst") {
  const int w = 160, h = 96;
  JobSystem jobs(2);
  const glm::vec3 sun(0.35f, 0.2f, -0.9f);
  std::vector<float> distance(size_t(w) * h);
  std::vector<glm::vec3> base(distance.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const bool sky = y < h / 3;
      distance[i] = sky ? INFINITY : 2.0f + 98.0f * float(h - y) / float(h - h / 3) + float(x % 7);
      base[i] = sky ? glm::vec3(3000.0f, 4000.0f, 6000.0f) : glm::vec3(800.0f, 700.0f, 600.0f);
    }
  for (const std::string name : {"fog_valley_sunrise.json", "fog_volumes.json"}) {
    CAPTURE(name);
    const FogSceneSettings s = scene_fog(name);
    FogProfileSettings p;  // the desktop profile's fog section is the default
    FogProfileSettings fixed = p;
    fixed.precision = FogPrecision::Fixed;
    FroxelFog in_float(p, s), in_fixed(fixed, s);
    std::vector<double> errors;
    Camera prev;
    for (int f = 0; f < 18; ++f) {
      const Camera cam = camera_at({-2.0 + 0.5 * std::min(f, 5), 2, 8}, {0, 1.5, -20}, w, h);
      const FrameView view = frame_view(cam, f ? prev : cam, f, f > 0, w, h);
      const ShadowMap shadow = wall_shadow(cam, sun);
      const LightEnvironment l = light(sun, 1e5f, 2000.0f);
      std::vector<glm::vec3> images[2];
      for (FroxelFog* fog : {&in_float, &in_fixed}) {
        fog->render(view, l, shadow, jobs, &distance);
        FrameBuffers b;
        b.resize(w, h);
        b.distance = distance;
        b.color = base;
        fog->composite(b, 0, 0, w, h);
        images[fog == &in_fixed] = b.color;
      }
      for (size_t i = 0; i < distance.size(); ++i) {
        const double a = luminance(glm::dvec3(images[0][i])), b = luminance(glm::dvec3(images[1][i]));
        errors.push_back(std::abs(b - a) / a);
      }
      prev = cam;
    }
    CHECK(in_fixed.stats().jitter_complete);  // the still view reached its mean
    double mean = 0.0;
    for (double e : errors) mean += e;
    mean /= double(errors.size());
    const double worst = *std::max_element(errors.begin(), errors.end());
    const double p95 = percentile_nearest_rank(errors, 95.0);
    MESSAGE(name << ": fixed against float, mean " << mean << ", p95 " << p95 << ", worst " << worst);
    CHECK(mean < 3e-4);
    CHECK(p95 < 1e-3);
    CHECK(worst < 4e-3);
  }
}

TEST_CASE("fixed-point transmittance never rises with depth, so in-scatter steps are never negative") {
  // Every Q16.16 log2 depth the integration can reach (it saturates at 32).
  uint16_t before = fx::exp2_neg_q15(0);
  CHECK(before == 32767);
  size_t rises = 0;
  for (uint32_t depth = 1; depth <= (uint32_t(32) << 16); ++depth) {
    const uint16_t t = fx::exp2_neg_q15(depth);
    rises += t > before;
    before = t;
  }
  CHECK(rises == 0);
  CHECK(before == 0);
  // The stored codes: non-increasing over all 65536, 0 at the top.
  size_t stored_rises = 0;
  for (uint32_t code = 1; code <= 0xFFFF; ++code)
    stored_rises += transmittance_q15(uint16_t(code)) > transmittance_q15(uint16_t(code - 1));
  CHECK(stored_rises == 0);
  CHECK(transmittance_q15(0xFFFF) == 0);
}

// One column of slices whose depths pass the top of every format: the
// depth sum, its Q5.11 code (65536 would wrap to 0 in 16 bits) and the hdr16
// radiance. The codes reach their tops and stay there.
TEST_CASE("fixed-point integration saturates at the edges of its formats instead of wrapping") {
  JobSystem jobs(1);
  for (float distance : {64.0f, 1e7f}) {  // 1e7 m: a slice's depth alone is past any range
    CAPTURE(distance);
    const FroxelGrid grid(8, 8, 8, 32, 0.1f, distance, 0.75f);
    const Camera cam = Camera::look_at({0, 2, 5}, {0, 2, -10}, 1.0f, 1.0f, 0.1f);
    const FroxelView view = make_froxel_view(grid, cam, jobs);
    // Extinction so that the depth reaches 32 log2 units (the cap) mid-column.
    const float sigma = 4.0f;
    const std::vector<FogDensity> density(grid.count(), FogDensity{glm::vec3(sigma), sigma});
    const std::vector<uint16_t> lit(grid.count(), Q15SunTerm::kOne);
    MediumLighting m;
    m.anisotropy = 0.99f;
    m.sun_direction = cam.forward;  // the phase's peak along the column
    m.sun_illuminance = glm::vec3(1e12f);  // radiance past hdr16's top (8.6e9)
    std::vector<FixedIntegratedFroxel> volume;
    integrate_columns(view, density, lit, m, {}, jobs, volume);
    const FixedIntegratedFroxel* column = volume.data();
    int depth_top = -1, radiance_top = -1;
    for (int k = 0; k < grid.nz(); ++k) {
      if (k > 0) {
        CHECK(column[k].optical_depth >= column[k - 1].optical_depth);
        CHECK(column[k].in_scatter[0] >= column[k - 1].in_scatter[0]);
      }
      if (depth_top < 0 && column[k].optical_depth == 0xFFFF) depth_top = k;
      if (radiance_top < 0 && column[k].in_scatter[0] == 0xFFFF) radiance_top = k;
      const IntegratedFroxel f = decode_froxel(grid, volume, size_t(k));
      CHECK(std::isfinite(f.in_scatter.x));
      CHECK(std::isfinite(f.extinction));
      CHECK(f.extinction >= 0.0f);
    }
    CHECK(depth_top >= 0);
    CHECK(depth_top < grid.nz() - 1);
    CHECK(radiance_top >= 0);
    CHECK(fx::decode_hdr16(column[grid.nz() - 1].in_scatter[0]) == fx::kHdr16Max);
    CHECK(transmittance_q15(column[grid.nz() - 1].optical_depth) == 0);
  }
}

TEST_CASE("q15 sun-term arithmetic at fully lit air's code stays within 0..32767") {
  using F = Q15SunTerm;
  // Lerps between the extremes at every weight stay between them.
  for (int w = 0; w <= 32767; ++w) {
    const auto up = F::lerp(0, F::kOne, int16_t(w)), down = F::lerp(F::kOne, 0, int16_t(w));
    REQUIRE(up <= F::kOne);
    REQUIRE(down <= F::kOne);
  }
  CHECK(F::lerp(F::kOne, F::kOne, F::weight(6.0f / 7.0f)) == F::kOne);
  CHECK(F::encode(1.0f) == F::kOne);
  CHECK(F::encode(1.0001f) == F::kOne);
  CHECK(F::encode(-0.5f) == 0);
  CHECK(F::encode(NAN) == 0);
  // No light change keeps the blend whole; a full change keeps (nearly) the current value.
  CHECK(F::scale_history_share(0, F::kOne, 0) == F::kOne);
  CHECK(F::scale_history_share(F::kOne, 0, 0) == 0);
  CHECK(F::scale_history_share(0, F::kOne, F::kOne) <= 1);
  // The filter's weights sum to 32768: a lit neighbourhood stays 32767, never 32768
  // (which a later lerp's int16 difference would wrap).
  JobSystem jobs(1);
  const FroxelGrid grid(24, 24, 8, 8, 0.1f, 64.0f, 0.75f);
  const FroxelView view = make_froxel_view(grid, Camera::look_at({0, 2, 5}, {0, 2, -10}, 1.0f, 1.0f, 0.1f), jobs);
  const std::vector<uint16_t> lit(grid.count(), F::kOne);
  std::vector<uint16_t> scratch, out;
  filter_slices(view, lit, jobs, scratch, out);
  CHECK(out == lit);
}


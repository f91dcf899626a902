// The froxel pipeline against closed forms of a homogeneous medium: with
// constant extinction sigma, scattering sigma_s, sun illuminance E (unshadowed)
// and ambient radiance La, a view ray through a slab of length l sees
//   T = exp(-sigma l),  L = sigma_s / sigma (p E + La) (1 - T).
#include <doctest/doctest.h>

#include <cmath>

#include "engine/core/math_constants.h"
#include "fog/fog_medium.h"
#include "fog/homogeneous_medium.h"
#include "fog/phase_function.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kW = 45, kH = 45;

void check_slab(FogPhase phase, float g, bool jitter) {
  JobSystem jobs(2);
  FogProfileSettings p;
  p.froxel_size_px = 5;  // odd: pixel 5i+2 sits on column i's centre ray
  p.slices = 32;
  p.fog_distance = 40.0f;
  p.jitter = jitter;
  const float sigma = 0.05f;
  FogSceneSettings s = uniform_fog(sigma, glm::vec3(0.8f, 0.6f, 0.4f), g);
  s.phase = phase;
  FroxelFog fog(p, s);
  const Camera cam = camera_at({0, 2, 0}, {0, 2, -10}, kW, kH);
  const LightEnvironment l = light({0.3f, 0.5f, -0.6f}, 1000.0f, 2.0f);
  const ShadowMap no_shadow;
  std::vector<float> distance(size_t(kW) * kH);
  const float distances[] = {0.05f, 0.3f, 5.3f, 17.0f, 39.9f, INFINITY, 1e6f};
  for (size_t i = 0; i < distance.size(); ++i) distance[i] = distances[i % 7];
  const glm::vec3 base(3.0f, 2.0f, 1.0f);
  const std::vector<glm::vec3> out =
      composite(fog, frame_view(cam, cam, 0, false, kW, kH), l, no_shadow, jobs, distance, base);
  const float near = 0.1f, far = 40.1f;
  int checked = 0;
  for (int y = 2; y < kH; y += 5)
    for (int x = 2; x < kW; x += 5) {
      const size_t i = size_t(y) * kW + x;
      const float d = std::clamp(distance[i], near, far);
      const glm::vec3 dir = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, kW, kH);
      const float phase_value = evaluate_phase(phase, glm::dot(dir, l.sun_direction), g);
      const float t = std::exp(-sigma * (d - near));
      const glm::vec3 expected =
          base * t + s.albedo * (phase_value * 1000.0f + 2.0f) * (1.0f - t);
      for (int c = 0; c < 3; ++c) CHECK(out[i][c] == doctest::Approx(expected[c]).epsilon(2e-4));
      ++checked;
    }
  CHECK(checked == 81);
}

}  // namespace

TEST_CASE("homogeneous slab: transmittance and single scattering match the closed form (isotropic)") {
  check_slab(FogPhase::HenyeyGreenstein, 0.0f, true);
}

TEST_CASE("homogeneous slab: closed form with anisotropic HG and Cornette-Shanks phase") {
  check_slab(FogPhase::HenyeyGreenstein, 0.6f, true);
  check_slab(FogPhase::CornetteShanks, -0.4f, false);
}

TEST_CASE("phase functions are normalised and their SH zonal coefficients match numerical projection") {
  for (FogPhase phase : {FogPhase::HenyeyGreenstein, FogPhase::CornetteShanks})
    for (float g : {-0.9f, -0.3f, 0.0f, 0.5f, 0.8f}) {
      // lambda_l = 2 pi int p(mu) P_l(mu) dmu, midpoint rule.
      const int n = 200000;
      double l0 = 0, l1 = 0, l2 = 0;
      for (int i = 0; i < n; ++i) {
        const double mu = -1.0 + (i + 0.5) * 2.0 / n;
        const double v = evaluate_phase(phase, float(mu), g) * 2.0 * kPiD * 2.0 / n;
        l0 += v;
        l1 += v * mu;
        l2 += v * 0.5 * (3 * mu * mu - 1);
      }
      const std::array<float, 3> z = phase_zonal_coefficients(phase, g);
      CHECK(l0 == doctest::Approx(1.0).epsilon(1e-3));
      CHECK(z[0] == doctest::Approx(l0).epsilon(1e-3));
      CHECK(z[1] == doctest::Approx(l1).epsilon(2e-3));
      CHECK(z[2] == doctest::Approx(l2).epsilon(2e-3));
    }
}

TEST_CASE("the froxel sample offset inverts the transmittance-proportional CDF of the slice") {
  // F(t) = (1 - exp(-sigma t)) / (1 - exp(-sigma dt)) on [0, dt]; the offset
  // for u must satisfy F(offset) = u, on both sides of the thin-slice series'
  // switch (a = sigma dt = 0.05) and in optically thick slices.
  const float dt = 2.0f;
  for (double a : {1e-6, 1e-3, 0.02, 0.0499, 0.0501, 0.3, 2.0, 12.0, 60.0}) {
    CAPTURE(a);
    const float sigma = float(a / dt);
    float previous = -1.0f;
    for (int i = 0; i < 64; ++i) {
      const float u = (float(i) + 0.5f) / 64.0f;
      const float t = importance_sample_offset(u, sigma, dt);
      REQUIRE(t >= 0.0f);
      REQUIRE(t <= dt);
      CHECK(t > previous);  // monotonic in u
      previous = t;
      const double cdf = -std::expm1(-double(sigma) * t) / -std::expm1(-a);
      CHECK(std::abs(cdf - u) < 2e-4);
    }
  }
}

TEST_CASE("height fog: the base extinction below the base, 0.001 of it at the maximum height, clear air above") {
  FogSceneSettings s;
  s.height_fog = true;
  s.base_height = 10.0f;
  s.max_height = 30.0f;
  s.extinction = 0.05f;
  s.albedo = glm::vec3(0.9f, 0.8f, 0.7f);
  FogMedium m(s);
  m.set_camera({100.0, 4.0, -3.0});  // positions are relative to the camera
  auto at_height = [&](float h) { return m.height_fog(glm::vec3(7.0f, h - 4.0f, 2.0f)); };
  CHECK(at_height(-50.0f).extinction == doctest::Approx(0.05f));
  CHECK(at_height(10.0f).extinction == doctest::Approx(0.05f));
  CHECK(at_height(30.0f).extinction == doctest::Approx(0.05f * 0.001f).epsilon(1e-4));
  // Exponential in between: halfway the geometric mean of the ends.
  CHECK(at_height(20.0f).extinction == doctest::Approx(0.05f * std::sqrt(0.001f)).epsilon(1e-4));
  const FogDensity d = at_height(17.0f);
  CHECK(d.scattering.x == doctest::Approx(0.9f * d.extinction));
  CHECK(d.scattering.z == doctest::Approx(0.7f * d.extinction));
  // Beyond twice the layer above the base (1e-6 of the base) the air is clear.
  CHECK(at_height(49.0f).extinction > 0.0f);
  CHECK(at_height(51.0f).extinction == 0.0f);
  s.height_fog = false;
  FogMedium off(s);
  off.set_camera({0.0, 0.0, 0.0});
  CHECK(off.height_fog(glm::vec3(0.0f, -100.0f, 0.0f)).extinction == 0.0f);
}

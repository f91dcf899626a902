// The sun's illuminance per point (the atmosphere's sun_at) reaches the
// integration through knots: sun_at at every kSunStride-th column's first and
// last slice centres, lerped across columns and along each column. For an
// illuminance affine in position (the atmosphere's transmittance over tens of
// metres of altitude is close to it) the lerp along a column is exact and the
// one across columns off only by the rays' curvature (the knots lie at equal
// distances, on an arc): the integrated volume must match per-slice sun_at
// within that.
#include <doctest/doctest.h>

#include <cmath>

#include "fog/phase_function.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

TEST_CASE("the integration applies sun_at's illuminance along and across columns") {
  JobSystem jobs(2);
  // 16:9 at 8 px: 80 columns, knots every 8 (about 9 degrees apart, where
  // the chord between two knots' points stays within 0.3% of the arc).
  const int w = 640, h = 360;
  const Camera cam = camera_at({0, 50, 0}, {30, 35, -100}, w, h);
  const FroxelGrid grid(w, h, 8, 24, cam.znear, 64.0f, 0.5f);
  const FroxelView view = make_froxel_view(grid, cam, jobs);
  const float sigma = 0.05f;
  std::vector<FogDensity> density(grid.count(), FogDensity{glm::vec3(0.8f * sigma), sigma});
  std::vector<float> visibility(grid.count());
  for (size_t i = 0; i < visibility.size(); ++i) visibility[i] = float((i * 7919) % 101) / 100.0f;

  // Brighter with altitude and towards +x, with another tint per channel.
  auto sun = [](const glm::vec3& p) {
    return glm::vec3(1000.0f, 900.0f, 700.0f) * (1.0f + 0.004f * (p.y - 50.0f)) +
           glm::vec3(3.0f, 1.0f, -2.0f) * p.x;
  };
  LightEnvironment light;
  light.sun_direction = glm::normalize(glm::vec3(0.3f, 0.5f, -0.8f));
  light.sun_illuminance = sun(glm::vec3(cam.position));
  light.sun_at = [&](const glm::vec3* p, glm::vec3* out, size_t n) {
    for (size_t i = 0; i < n; ++i) out[i] = sun(p[i]);
  };
  MediumLighting lighting;
  lighting.anisotropy = 0.4f;
  lighting.sun_direction = light.sun_direction;
  lighting.sun_illuminance = light.sun_illuminance;
  lighting.light = &light;
  lighting.camera_position = cam.position;

  std::vector<IntegratedFroxel> volume, uniform_volume;
  integrate_columns(view, density, visibility, lighting, sun_knots(view, lighting, jobs), jobs, volume, {});
  integrate_columns(view, density, visibility, lighting, {}, jobs, uniform_volume, {});

  double worst = 0.0, worst_uniform = 0.0;
  for (int y = 0; y < grid.ny(); ++y)
    for (int x = 0; x < grid.nx(); ++x) {
      // The definition: the exact recurrence with sun_at at each slice centre.
      const glm::vec3 dir = view.directions[size_t(y) * grid.nx() + x];
      const float phase = evaluate_phase(lighting.phase, glm::dot(dir, light.sun_direction), lighting.anisotropy);
      glm::dvec3 in_scatter(0.0);
      double transmittance = 1.0;
      for (int k = 0; k < grid.nz(); ++k) {
        const size_t i = grid.index(x, y, k);
        const glm::vec3 world = glm::vec3(cam.position) + dir * grid.center(k);
        const double opacity = -std::expm1(-double(sigma) * grid.thickness(k));
        const glm::dvec3 source =
            glm::dvec3(density[i].scattering) * glm::dvec3(sun(world)) * double(phase * visibility[i]);
        in_scatter += source * (transmittance * opacity / sigma);
        transmittance *= 1.0 - opacity;
        const double scale = std::max(in_scatter.x, 1e-3);
        for (int c = 0; c < 3; ++c) {
          worst = std::max(worst, std::abs(double(volume[i].in_scatter[c]) - in_scatter[c]) / scale);
          const double off = std::abs(double(uniform_volume[i].in_scatter[c]) - in_scatter[c]);
          worst_uniform = std::max(worst_uniform, off / scale);
        }
        CHECK(volume[i].transmittance == doctest::Approx(transmittance).epsilon(1e-5));
      }
    }
  CHECK(worst < 2e-3);
  // Not vacuous: the camera's illuminance everywhere is far off.
  CHECK(worst_uniform > 0.03);
}

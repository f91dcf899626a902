// Point and spot lights (KHR_lights_punctual) in shading: inverse-square
// falloff, the range window, the spot cone, the same BRDF as the sun, and no
// shadows.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/scene/camera.h"
#include "engine/shading/punctual_lights.h"
#include "engine/shading/shade_surface.h"

using namespace cr;

namespace {

Material dielectric(float albedo) {
  Material m;
  m.base_color_factor = glm::vec4(glm::vec3(albedo), 1.0f);
  m.metallic_factor = 0.0f;
  m.roughness_factor = 1.0f;
  return m;
}

SurfaceSample flat_sample() {
  SurfaceSample s;
  s.normal = {0.0f, 1.0f, 0.0f};
  return s;
}

PunctualLight point_light(glm::vec3 position, float intensity) {
  PunctualLight l;
  l.position = position;
  l.intensity = intensity;
  return l;
}

// Radiance of the point at the origin (normal +Y) seen from `camera` under
// the scene's lights alone (no sun, no sky).
glm::vec3 radiance(const Scene& scene, const Material& m, glm::dvec3 camera = {0.0, 3.0, 0.0},
                   const ShadowMap* shadow = nullptr) {
  const LightEnvironment dark;
  return glm::vec3(shade_surface({.scene = &scene, .light = &dark, .shadow = shadow, .camera_position = camera}, m,
                                 flat_sample()));
}

}  // namespace

TEST_CASE("point light: I / d^2 through the glTF BRDF; the diffuse share is (1 - F0) albedo / pi * I / d^2") {
  const float d = 2.5f, intensity = 800.0f;
  Scene scene;
  scene.lights = {point_light({0.0f, d, 0.0f}, intensity)};
  // Light and viewer straight above: Fresnel F = F0 = 0.04, so the diffuse
  // lobe keeps 0.96 of the Lambertian albedo / pi; the specular lobe does
  // not depend on albedo, so white minus black is the diffuse part alone.
  const glm::vec3 white = radiance(scene, dielectric(1.0f)), black = radiance(scene, dielectric(0.0f));
  const float lambert = 0.96f / kPi * intensity / (d * d);
  for (int c = 0; c < 3; ++c) CHECK(white[c] - black[c] == doctest::Approx(lambert).epsilon(1e-5));
  // The specular part at normal incidence, roughness 1: D = 1/pi, Vis = 1/4, F = 0.04.
  CHECK(black.r == doctest::Approx(0.04f * 0.25f / kPi * intensity / (d * d)).epsilon(1e-5));

  // Twice as far: a quarter.
  Scene far = scene;
  far.lights[0].position.y = 2.0f * d;
  CHECK(radiance(far, dielectric(0.6f)).g == doctest::Approx(0.25f * radiance(scene, dielectric(0.6f)).g).epsilon(1e-5));

  // The light's colour scales its intensity per channel.
  Scene coloured = scene;
  coloured.lights[0].color = {1.0f, 0.5f, 0.25f};
  const glm::vec3 c = radiance(coloured, dielectric(0.6f)), w = radiance(scene, dielectric(0.6f));
  CHECK(c.g == doctest::Approx(0.5f * w.g).epsilon(1e-6));
  CHECK(c.b == doctest::Approx(0.25f * w.b).epsilon(1e-6));
}

TEST_CASE("point light: equals a sun of illuminance I / d^2 from the light's direction, at any angle") {
  const glm::vec3 to_light = glm::normalize(glm::vec3(0.6f, 1.0f, -0.3f));
  const float d = 7.0f, intensity = 5e4f;
  Scene scene;
  scene.lights = {point_light(to_light * d, intensity)};
  Material m = dielectric(0.7f);
  m.metallic_factor = 0.4f;
  m.roughness_factor = 0.35f;
  const glm::dvec3 camera(-2.0, 4.0, 1.5);
  LightEnvironment sun;
  sun.sun_direction = to_light;
  sun.sun_illuminance = glm::vec3(intensity / (d * d));
  const Scene no_lights;
  const glm::vec3 expected(
      shade_surface({.scene = &no_lights, .light = &sun, .camera_position = camera}, m, flat_sample()));
  const glm::vec3 got = radiance(scene, m, camera);
  for (int k = 0; k < 3; ++k) CHECK(got[k] == doctest::Approx(expected[k]).epsilon(1e-4));
  CHECK(got.r > 0.0f);
  // From below the surface: nothing.
  scene.lights[0].position = -to_light * d;
  CHECK(radiance(scene, m, camera) == glm::vec3(0.0f));
}

TEST_CASE("point light: the range window is zero at the range and the recommended clamp(1 - (d/r)^4) inside") {
  CHECK(range_window(10.0f, 1.0f / 10.0f) == 0.0f);
  CHECK(range_window(12.0f, 1.0f / 10.0f) == 0.0f);
  CHECK(range_window(5.0f, 1.0f / 10.0f) == doctest::Approx(1.0f - 1.0f / 16.0f));
  CHECK(range_window(1e6f, 0.0f) == 1.0f);  // no range: unlimited
  const float d = 4.0f;
  Scene scene;
  scene.lights = {point_light({0.0f, d, 0.0f}, 1000.0f)};
  const glm::vec3 unlimited = radiance(scene, dielectric(0.8f));
  scene.lights[0].range = d;
  CHECK(radiance(scene, dielectric(0.8f)) == glm::vec3(0.0f));
  scene.lights[0].range = 2.0f * d;
  CHECK(radiance(scene, dielectric(0.8f)).r == doctest::Approx((1.0f - 1.0f / 16.0f) * unlimited.r).epsilon(1e-5));
}

TEST_CASE("spot light: full inside the inner cone, zero outside the outer one, smooth and squared between") {
  const float inner = 0.2f, outer = 0.6f, d = 3.0f;
  const float scale = 1.0f / (std::cos(inner) - std::cos(outer)), offset = -std::cos(outer) * scale;
  CHECK(cone_attenuation(std::cos(0.1f), scale, offset) == 1.0f);
  CHECK(cone_attenuation(std::cos(0.7f), scale, offset) == 0.0f);
  const float mid = 0.4f, t = (std::cos(mid) - std::cos(outer)) * scale;
  CHECK(cone_attenuation(std::cos(mid), scale, offset) == doctest::Approx(t * t));

  Scene point;
  point.lights = {point_light({0.0f, d, 0.0f}, 2000.0f)};
  const glm::vec3 full = radiance(point, dielectric(0.5f));
  // The spot above the point, its axis tilted away from it by `angle`.
  auto spot_at = [&](float angle) {
    Scene scene = point;
    PunctualLight& spot = scene.lights[0];
    spot.type = PunctualLight::Type::Spot;
    spot.inner_cone_rad = inner;
    spot.outer_cone_rad = outer;
    spot.direction = {std::sin(angle), -std::cos(angle), 0.0f};
    return radiance(scene, dielectric(0.5f)).r;
  };
  CHECK(spot_at(0.0f) == doctest::Approx(full.r).epsilon(1e-6));
  CHECK(spot_at(0.15f) == doctest::Approx(full.r).epsilon(1e-6));
  CHECK(spot_at(0.65f) == 0.0f);
  CHECK(spot_at(mid) == doctest::Approx(t * t * full.r).epsilon(1e-4));
  CHECK(punctual_light_terms(point.lights[0]).cone_scale == 0.0f);  // point lights: no cone
}

TEST_CASE("punctual lights cast no shadow: the shadow map is the sun's") {
  Scene scene;
  scene.lights = {point_light({0.0f, 2.0f, 0.0f}, 500.0f)};
  ShadowMap shadow = fit_shadow_map(Camera::look_at({0, 2, 5}, {0, 0, 0}, 1.0f, 1.0f, 0.1f), {0.0f, 1.0f, 0.0f},
                                    20.0f, 64, 1, glm::vec3(-10.0f), glm::vec3(10.0f));
  std::fill(shadow.depth.begin(), shadow.depth.end(), 1.0f);  // an occluder over everything
  const glm::vec3 open = radiance(scene, dielectric(0.5f));
  CHECK(open.r > 0.0f);
  CHECK(radiance(scene, dielectric(0.5f), {0.0, 3.0, 0.0}, &shadow) == open);
}

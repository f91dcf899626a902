#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/math_constants.h"
#include "engine/shading/brdf.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/sh_lighting.h"
#include "engine/shading/shade_surface.h"

using namespace cr;

namespace {

// A 1x1 linear (or sRGB) image of one RGBA8 texel.
Image texel_image_rgba(uint8_t r, uint8_t g, uint8_t b, uint8_t a, bool srgb = false) {
  Image img;
  img.srgb = srgb;
  img.mips.push_back(MipLevel{1, 1, {r, g, b, a}});
  return img;
}

Material white_dielectric(float roughness) {
  Material m;
  m.metallic_factor = 0.0f;
  m.roughness_factor = roughness;
  return m;
}

SurfaceSample flat_surface_sample() {
  SurfaceSample s;
  s.position = {0, 0, 0};
  s.normal = {0, 1, 0};
  s.tangent = {1, 0, 0, 1};
  return s;
}

bool finite(const glm::vec4& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && std::isfinite(c.a);
}

}  // namespace

TEST_CASE("shade: a white rough dielectric under uniform sky reflects the sky's radiance") {
  Scene scene;
  LightEnvironment light;
  light.ambient_sh = sh_constant_radiance(glm::vec3(1000.0f));
  const ShadingInputs in{&scene, &light, nullptr, glm::dvec3(0.0)};
  for (float elevation : {90.0f, 45.0f, 10.0f}) {
    const float e = glm::radians(elevation);
    ShadingInputs view = in;
    view.camera_position = glm::dvec3(std::cos(e), std::sin(e), 0.0) * 5.0;
    // Diffuse gets what the specular lobe leaves: E/pi (1 - albedo) + L albedo = L.
    const glm::vec4 c = shade_surface(view, white_dielectric(1.0f), flat_surface_sample());
    CHECK(c.r == doctest::Approx(1000.0f).epsilon(1e-4));
    CHECK(c.a == 1.0f);
  }
}

TEST_CASE("shade: sun term is BRDF * n.l * E, scaled by shadow visibility") {
  Scene scene;
  LightEnvironment light;
  light.sun_direction = glm::normalize(glm::vec3(1, 2, 0));
  light.sun_illuminance = glm::vec3(1e5f, 9e4f, 8e4f);
  const ShadingInputs in{&scene, &light, nullptr, glm::dvec3(-1.0, 3.0, 0.5)};
  Material m;
  m.base_color_factor = glm::vec4(0.8f, 0.4f, 0.2f, 1.0f);
  m.metallic_factor = 0.3f;
  m.roughness_factor = 0.4f;
  const SurfaceSample s = flat_surface_sample();
  const glm::vec3 v = glm::normalize(glm::vec3(-1, 3, 0.5f));
  const glm::vec3 expected = evaluate_brdf({glm::vec3(m.base_color_factor), 0.3f, 0.4f}, s.normal, v, light.sun_direction) *
                             glm::dot(s.normal, light.sun_direction) * light.sun_illuminance;
  const glm::vec4 c = shade_surface(in, m, s);
  for (int k = 0; k < 3; ++k) CHECK(c[k] == doctest::Approx(expected[k]).epsilon(1e-5));

  // sun_at overrides the constant illuminance.
  LightEnvironment attenuated = light;
  attenuated.sun_at = [](const glm::vec3*, glm::vec3* out, size_t n) {
    for (size_t i = 0; i < n; ++i) out[i] = glm::vec3(5e4f, 4.5e4f, 4e4f);
  };
  const glm::vec4 half = shade_surface({&scene, &attenuated, nullptr, in.camera_position}, m, s);
  for (int k = 0; k < 3; ++k) CHECK(half[k] == doctest::Approx(0.5f * expected[k]).epsilon(1e-5));

  // A shadow map that records an occluder over everything removes the sun.
  ShadowMap shadow = fit_shadow_map(Camera::look_at({0, 2, 5}, {0, 0, 0}, 1.0f, 1.0f, 0.1f), light.sun_direction,
                                    20.0f, 64, 1, glm::vec3(-10.0f), glm::vec3(10.0f));
  std::fill(shadow.depth.begin(), shadow.depth.end(), 1.0f);
  const glm::vec4 shadowed = shade_surface({&scene, &light, &shadow, in.camera_position}, m, s);
  CHECK(shadowed.r == 0.0f);
  // An empty one (size 0) leaves it lit.
  const ShadowMap none;
  CHECK(shade_surface({&scene, &light, &none, in.camera_position}, m, s).r == doctest::Approx(c.r));
}

TEST_CASE("shade: occlusion darkens only the ambient term; emission adds the emissive luminance per unit") {
  Scene scene;
  scene.images.push_back(texel_image_rgba(0, 0, 0, 255));  // occlusion 0
  LightEnvironment light;
  light.ambient_sh = sh_constant_radiance(glm::vec3(100.0f));
  light.sun_direction = {0, 1, 0};
  light.sun_illuminance = glm::vec3(1000.0f);
  const ShadingInputs in{&scene, &light, nullptr, glm::dvec3(0.0, 2.0, 0.0)};
  Material m = white_dielectric(0.8f);
  const glm::vec4 open = shade_surface(in, m, flat_surface_sample());
  m.occlusion.image = 0;
  m.occlusion.scale = 1.0f;
  const glm::vec4 occluded = shade_surface(in, m, flat_surface_sample());
  LightEnvironment sun_only = light;
  sun_only.ambient_sh = {};
  const glm::vec4 direct = shade_surface({&scene, &sun_only, nullptr, in.camera_position}, white_dielectric(0.8f), flat_surface_sample());
  CHECK(occluded.r == doctest::Approx(direct.r));
  CHECK(open.r > direct.r + 50.0f);
  // Half strength: halfway (the specular occlusion of a rough lobe seen head-on is
  // ao within 2e-4: specular_occlusion.h).
  m.occlusion.scale = 0.5f;
  CHECK(shade_surface(in, m, flat_surface_sample()).r == doctest::Approx(0.5f * (open.r + direct.r)).epsilon(1e-4));

  LightEnvironment dark;
  Material glow = white_dielectric(1.0f);
  glow.base_color_factor = glm::vec4(0, 0, 0, 1);
  glow.emissive_factor = {1.0f, 0.5f, 0.0f};
  const ShadingInputs glowing{.scene = &scene, .light = &dark, .camera_position = in.camera_position,
                              .emissive_luminance = 800.0f};
  const glm::vec4 e = shade_surface(glowing, glow, flat_surface_sample());
  CHECK(e.r == doctest::Approx(800.0f));
  CHECK(e.g == doctest::Approx(400.0f));
  CHECK(e.b == 0.0f);
  // KHR_materials_emissive_strength multiplies the factor; strength 0 turns it off.
  glow.emissive_strength = 6.5f;
  CHECK(shade_surface(glowing, glow, flat_surface_sample()).r == doctest::Approx(6.5f * 800.0f));
  glow.emissive_strength = 0.0f;
  CHECK(shade_surface(glowing, glow, flat_surface_sample()).r == 0.0f);
}

TEST_CASE("shade: textures, vertex colour and alpha") {
  Scene scene;
  scene.images.push_back(texel_image_rgba(255, 128, 0, 128, true));   // base colour (sRGB)
  scene.images.push_back(texel_image_rgba(0, 64, 255, 255));          // metallic-roughness: G rough, B metal
  scene.images.push_back(texel_image_rgba(128, 128, 255, 255));       // flat normal map
  Material m;
  m.base_color_factor = glm::vec4(1.0f, 1.0f, 1.0f, 0.5f);
  m.base_color.image = 0;
  m.metallic_roughness.image = 1;
  m.roughness_factor = 0.5f;
  m.metallic_factor = 0.5f;
  m.normal.image = 2;
  SurfaceSample s = flat_surface_sample();
  s.color = glm::vec4(1.0f, 1.0f, 1.0f, 0.5f);

  CHECK(material_alpha(scene, m, s) == doctest::Approx(0.5f * 128.0f / 255.0f * 0.5f));
  const MaterialSample ms = evaluate_material(scene, m, s, 1.0f);
  CHECK(ms.base_color.r == doctest::Approx(1.0f));
  CHECK(ms.base_color.g == doctest::Approx(0.2158605f).epsilon(1e-4));  // sRGB 128 decoded
  CHECK(ms.roughness == doctest::Approx(0.5f * 64.0f / 255.0f));
  CHECK(ms.metallic == doctest::Approx(0.5f));
  CHECK(glm::dot(ms.normal, s.normal) > 0.9999f);

  // A tilted normal map bends the normal towards +tangent.
  scene.images[2] = texel_image_rgba(255, 128, 128, 255);
  m.normal.scale = 1.0f;
  CHECK(evaluate_material(scene, m, s, 1.0f).normal.x > 0.7f);

  LightEnvironment light;
  light.ambient_sh = sh_constant_radiance(glm::vec3(1.0f));
  m.alpha_mode = AlphaMode::Blend;
  CHECK(shade_surface({&scene, &light, nullptr, glm::dvec3(0, 1, 0)}, m, s).a == doctest::Approx(material_alpha(scene, m, s)));
  m.alpha_mode = AlphaMode::Mask;
  CHECK(shade_surface({&scene, &light, nullptr, glm::dvec3(0, 1, 0)}, m, s).a == 1.0f);
}

TEST_CASE("shade: no NaN for degenerate normals, grazing views or a camera on the surface") {
  Scene scene;
  LightEnvironment light;
  light.sun_direction = glm::normalize(glm::vec3(1, 1e-6f, 0));
  light.sun_illuminance = glm::vec3(1e5f);
  light.ambient_sh = sh_constant_radiance(glm::vec3(3000.0f));
  light.ambient_sh[3] = glm::vec3(-5000.0f);  // ringing: negative radiance in places
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const glm::vec3& normal : {glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(nan)}) {
    for (const glm::dvec3& camera : {glm::dvec3(0.0), glm::dvec3(1, 1e-7, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, -3, 0)}) {
      for (float roughness : {0.0f, 0.5f, 1.0f, nan}) {
        for (float metallic : {0.0f, 1.0f}) {
          SurfaceSample s = flat_surface_sample();
          s.normal = normal;
          Material m;
          m.roughness_factor = roughness;
          m.metallic_factor = metallic;
          const glm::vec4 c = shade_surface({&scene, &light, nullptr, camera}, m, s);
          CHECK(finite(c));
          CHECK(c.r >= 0.0f);
        }
      }
    }
  }
}

TEST_CASE("shade: one SurfaceShader reused over many points gives shade_surface's results bit for bit") {
  Scene scene;
  scene.images.push_back(texel_image_rgba(200, 90, 30, 255, true));
  LightEnvironment light;
  light.sun_direction = glm::vec3(0.3f, 0.8f, -0.2f);  // not unit: the shader normalises it once
  light.sun_illuminance = glm::vec3(9e4f, 8e4f, 7e4f);
  for (const bool constant_sky : {true, false}) {
    light.ambient_sh = sh_constant_radiance(glm::vec3(2000.0f, 2500.0f, 3000.0f));
    if (!constant_sky) light.ambient_sh[2] = glm::vec3(400.0f, 300.0f, -100.0f);
    ShadowMap shadow = fit_shadow_map(Camera::look_at({0, 2, 5}, {0, 0, 0}, 1.0f, 1.0f, 0.1f),
                                      glm::normalize(light.sun_direction), 20.0f, 64, 1, glm::vec3(-10.0f),
                                      glm::vec3(10.0f));
    // An occluder over half of the map: lit, shadowed and penumbra points.
    for (size_t i = 0; i < shadow.depth.size(); ++i) shadow.depth[i] = (i % 64) < 32 ? 1.0f : 0.0f;
    const ShadingInputs in{&scene, &light, &shadow, glm::dvec3(1.0, 3.0, 4.0)};
    const SurfaceShader shader(in);
    Material m;
    m.base_color.image = 0;
    m.metallic_factor = 0.2f;
    m.roughness_factor = 0.6f;
    for (int i = 0; i < 64; ++i) {
      SurfaceSample s = flat_surface_sample();
      s.position = glm::vec3(-8.0f + 0.25f * float(i), 0.0f, 0.1f * float(i % 7));
      s.normal = glm::normalize(glm::vec3(0.1f * float(i % 5) - 0.2f, 1.0f, 0.05f * float(i % 3)));
      const glm::vec4 a = shader.shade(m, s);
      const glm::vec4 b = shade_surface(in, m, s);
      CHECK(a == b);
    }
  }
}

TEST_CASE("shade: unlit materials give base colour * the emissive luminance, whatever the light; alpha still applies") {
  Scene scene;
  scene.images.push_back(texel_image_rgba(255, 128, 0, 128, true));
  LightEnvironment light;
  light.sun_direction = {0, 1, 0};
  light.sun_illuminance = glm::vec3(1e5f);
  light.ambient_sh = sh_constant_radiance(glm::vec3(3000.0f));
  PunctualLight lamp;
  lamp.position = {0.0f, 1.0f, 0.0f};
  lamp.intensity = 1e4f;
  scene.lights = {lamp};
  ShadowMap shadow = fit_shadow_map(Camera::look_at({0, 2, 5}, {0, 0, 0}, 1.0f, 1.0f, 0.1f), light.sun_direction,
                                    20.0f, 64, 1, glm::vec3(-10.0f), glm::vec3(10.0f));
  std::fill(shadow.depth.begin(), shadow.depth.end(), 1.0f);  // the sun shadowed everywhere
  Material m;
  m.unlit = true;
  m.base_color_factor = glm::vec4(0.5f, 1.0f, 1.0f, 0.5f);
  m.base_color.image = 0;
  m.emissive_factor = glm::vec3(1.0f);  // ignored by unlit materials
  SurfaceSample s = flat_surface_sample();
  s.color = glm::vec4(1.0f, 0.5f, 1.0f, 1.0f);
  const float luminance = 2500.0f;
  const glm::vec3 base = glm::vec3(m.base_color_factor) * glm::vec3(sample_material_texture(scene, m.base_color, s)) *
                         glm::vec3(s.color);
  const ShadowMap* maps[] = {nullptr, &shadow};
  for (const ShadowMap* sm : maps) {
    for (const glm::dvec3 camera : {glm::dvec3(0, 2, 0), glm::dvec3(3, 0.5, -1)}) {
      const glm::vec4 c = shade_surface({&scene, &light, sm, camera, luminance}, m, s);
      for (int k = 0; k < 3; ++k) CHECK(c[k] == doctest::Approx(base[k] * luminance).epsilon(1e-6));
      CHECK(c.a == 1.0f);
    }
  }
  m.alpha_mode = AlphaMode::Blend;
  CHECK(shade_surface({&scene, &light, nullptr, glm::dvec3(0, 2, 0), luminance}, m, s).a ==
        doctest::Approx(material_alpha(scene, m, s)));
  // Unlit materials need neither tangents nor TEXCOORD_1 unless their base colour reads it.
  m.normal.image = 0;
  m.emissive = {.image = 0, .texcoord = 1};
  CHECK_FALSE(needs_tangent(m));
  CHECK_FALSE(needs_uv1(m));
}

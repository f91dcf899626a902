// KHR_lights_punctual point and spot lights: placed by their nodes, with
// colour, intensity, range and cone angles checked; the first directional
// light stays the sun.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/gltf_loader.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

// A scene whose nodes each carry one of `lights`, node i placed by `translations[i]`.
GltfBuilder lights_scene(const nlohmann::json& lights) {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", lights}}}};
  nlohmann::json roots = nlohmann::json::array();
  for (size_t i = 0; i < lights.size(); ++i) {
    roots.push_back(b.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}}));
  }
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
  return b;
}

}  // namespace

TEST_CASE("point and spot lights are placed by their nodes; the first directional light is the sun") {
  GltfBuilder b = lights_scene({
      {{"type", "point"}, {"name", "bulb"}, {"intensity", 40.0}, {"color", {1.0, 0.5, 0.25}}, {"range", 8.0}},
      {{"type", "directional"}, {"intensity", 2.0}},
      {{"type", "spot"}, {"name", "torch"}, {"intensity", 100.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
      {{"type", "directional"}, {"intensity", 7.0}},
      {{"type", "spot"}, {"spot", nlohmann::json::object()}},
  });
  b.doc["nodes"][0]["translation"] = {1.0, 2.0, 3.0};
  // Spot pitched down by 90 degrees about X, under a translated parent.
  const glm::quat pitch = glm::angleAxis(glm::radians(-90.0f), glm::vec3(1, 0, 0));
  b.doc["nodes"][2]["rotation"] = {pitch.x, pitch.y, pitch.z, pitch.w};
  int parent = b.add("nodes", {{"translation", {0.0, 5.0, 0.0}}, {"children", {2}}});
  b.doc["scenes"][0]["nodes"] = {0, 1, parent, 3, 4};
  cr::Scene s = cr::load_gltf(b.write("lights.gltf"));

  REQUIRE(s.lights.size() == 3);
  const cr::PunctualLight& bulb = s.lights[0];
  CHECK(bulb.type == cr::PunctualLight::Type::Point);
  CHECK(bulb.name == "bulb");
  CHECK(bulb.position == glm::vec3(1, 2, 3));
  CHECK(bulb.color == glm::vec3(1.0f, 0.5f, 0.25f));
  CHECK(bulb.intensity == 40.0f);
  CHECK(bulb.range == 8.0f);

  const cr::PunctualLight& torch = s.lights[1];
  CHECK(torch.type == cr::PunctualLight::Type::Spot);
  CHECK(torch.position == glm::vec3(0, 5, 0));
  CHECK(glm::length(torch.direction - glm::vec3(0, -1, 0)) < 1e-6f);  // the node's -Z, pitched down
  CHECK(torch.inner_cone_rad == doctest::Approx(0.2));
  CHECK(torch.outer_cone_rad == doctest::Approx(0.5));
  CHECK(torch.range == 0.0f);  // no range: unlimited
  CHECK(torch.color == glm::vec3(1.0f));

  const cr::PunctualLight& plain = s.lights[2];  // spec defaults
  CHECK(plain.intensity == 1.0f);
  CHECK(plain.inner_cone_rad == 0.0f);
  CHECK(plain.outer_cone_rad == doctest::Approx(glm::quarter_pi<double>()));
  CHECK(glm::length(plain.direction - glm::vec3(0, 0, -1)) < 1e-6f);

  REQUIRE(s.sun.has_value());
  CHECK(s.sun->intensity == 2.0f);  // the first directional light; the second is warned about
}

TEST_CASE("LightsPunctualLamp has five point lights where its nodes put them (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  CHECK_FALSE(s.sun.has_value());
  REQUIRE(s.lights.size() == 5);
  struct Expected {
    const char* name;
    glm::vec3 position;
    float intensity;
    glm::vec3 color;
  };
  // Nodes 3..7 in scene order, their matrices' translations, and their lights.
  const Expected expected[5] = {
      {"Point", {0.04622355f, 0.90779734f, 0.00669663f}, 15.0f, {1.0f, 0.63187498f, 0.23909976f}},
      {"Point.002", {0.17545623f, -0.76421988f, -0.00570408f}, 1.5f, {1.0f, 1.0f, 1.0f}},
      {"Point.003", {0.13761821f, 2.0669837f, -1.17898643f}, 80.0f, {0.2122308f, 0.59061903f, 0.55834055f}},
      {"Point.001", {0.04428900f, 0.25436437f, -1.20903242f}, 80.0f, {0.2122308f, 0.59061903f, 0.55834055f}},
      {"Point.004", {0.29202104f, 1.03239989f, 1.55891597f}, 180.0f, {1.0f, 0.62783653f, 0.50124037f}},
  };
  for (int i = 0; i < 5; ++i) {
    CAPTURE(i);
    const cr::PunctualLight& l = s.lights[i];
    CHECK(l.type == cr::PunctualLight::Type::Point);
    CHECK(l.name == expected[i].name);
    CHECK(glm::length(l.position - expected[i].position) < 1e-5f);
    CHECK(l.intensity == expected[i].intensity);
    CHECK(glm::length(l.color - expected[i].color) < 1e-6f);
    CHECK(l.range == 0.0f);
  }
}

TEST_CASE("bad punctual lights are rejected with the light and the rule") {
  auto one_light = [](const std::string& name, nlohmann::json light) {
    return lights_scene(nlohmann::json::array({std::move(light)})).write(name);
  };
  expect_gltf_rejected(one_light("light_negative_range.gltf", {{"type", "point"}, {"range", -1.0}}),
                       "light 0 range must be a finite number > 0");
  expect_gltf_rejected(one_light("light_zero_range.gltf", {{"type", "point"}, {"range", 0.0}}),
                       "light 0 range must be a finite number > 0");
  expect_gltf_rejected(one_light("light_string_range.gltf", {{"type", "point"}, {"range", "far"}}),
                       "light 0 range must be a finite number > 0");
  expect_gltf_rejected(one_light("light_inner_ge_outer.gltf",
                                 {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.6}}}}),
                       "0 <= innerConeAngle < outerConeAngle <= pi/2");
  expect_gltf_rejected(one_light("light_outer_too_wide.gltf", {{"type", "spot"}, {"spot", {{"outerConeAngle", 2.0}}}}),
                       "0 <= innerConeAngle < outerConeAngle <= pi/2");
  expect_gltf_rejected(one_light("light_negative_inner.gltf", {{"type", "spot"}, {"spot", {{"innerConeAngle", -0.1}}}}),
                       "0 <= innerConeAngle < outerConeAngle <= pi/2");
  expect_gltf_rejected(one_light("light_negative_color.gltf", {{"type", "point"}, {"color", {1.0, -1.0, 0.0}}}),
                       "light 0 color must be 3 finite non-negative numbers");
  expect_gltf_rejected(one_light("light_unknown_type.gltf", {{"type", "area"}}), "light 0 has unknown type \"area\"");
  expect_gltf_rejected(one_light("light_string_intensity.gltf", {{"type", "point"}, {"intensity", "bright"}}),
                       "light 0 intensity must be a finite number >= 0");
  expect_gltf_rejected(one_light("light_negative_intensity.gltf", {{"type", "point"}, {"intensity", -2.0}}),
                       "light 0 intensity must be a finite number >= 0");
}

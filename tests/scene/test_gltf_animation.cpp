// Animations: sampler interpolation (closed forms), node transforms posed
// at a time, the scene file's choice of animation, and malformed
// animations rejected with one clear error.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/core/error.h"
#include "engine/scene/animation_sampling.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"
#include "engine/scene/scene_description.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

cr::AnimationSampler sampler(cr::Interpolation interpolation, std::vector<float> times, std::vector<float> values,
                             int components) {
  cr::AnimationSampler s;
  s.interpolation = interpolation;
  s.times = std::move(times);
  s.values = std::move(values);
  s.components = components;
  return s;
}

// Angle between two rotations.
double angle_between(const glm::dquat& a, const glm::dquat& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(a, b))));
}

// Node 0 draws a triangle; `animation` (channels and samplers) is added as
// the file's only animation, with accessors made by `add`.
template <typename AddAccessors>
std::string animated_file(const std::string& name, AddAccessors add) {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("animations", add(b));
  return b.write(name);
}

nlohmann::json one_channel(const std::string& path, int input, int output, const char* interpolation = "LINEAR",
                           int node = 0) {
  return {{"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}},
          {"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}}};
}

}  // namespace

TEST_CASE("LINEAR and STEP samplers: midpoints, keys, and held ends") {
  const cr::AnimationSampler linear = sampler(cr::Interpolation::Linear, {1, 3}, {1, 2, 3, 5, 6, 7}, 3);
  CHECK(cr::sample_values(linear, 2.0) == std::vector<double>{3, 4, 5});
  CHECK(cr::sample_values(linear, 1.5) == std::vector<double>{2, 3, 4});
  CHECK(cr::sample_values(linear, 0.0) == std::vector<double>{1, 2, 3});  // before the first key
  CHECK(cr::sample_values(linear, 9.0) == std::vector<double>{5, 6, 7});  // after the last
  const cr::AnimationSampler step = sampler(cr::Interpolation::Step, {0, 1, 2}, {10, 20, 30}, 1);
  CHECK(cr::sample_values(step, 0.99)[0] == 10.0);
  CHECK(cr::sample_values(step, 1.0)[0] == 20.0);
  CHECK(cr::sample_values(step, 1.5)[0] == 20.0);
  CHECK(cr::sample_values(step, 7.0)[0] == 30.0);
  const cr::AnimationSampler single = sampler(cr::Interpolation::Linear, {0.5f}, {4}, 1);
  CHECK(cr::sample_values(single, 0.0)[0] == 4.0);
  CHECK(cr::sample_values(single, 2.0)[0] == 4.0);
}

TEST_CASE("CUBICSPLINE: the Hermite spline with tangents scaled by the key interval") {
  // Keys at 0 and 2: (in-tangent, value, out-tangent) = (0, 1, 3) and (-1, 5, 0).
  const cr::AnimationSampler s = sampler(cr::Interpolation::CubicSpline, {0, 2}, {0, 1, 3, -1, 5, 0}, 1);
  CHECK(cr::sample_values(s, 0.0)[0] == 1.0);
  CHECK(cr::sample_values(s, 2.0)[0] == 5.0);
  // u = 1/2: 0.5*1 + 2*0.125*3 + 0.5*5 + 2*(-0.125)*(-1).
  CHECK(cr::sample_values(s, 1.0)[0] == doctest::Approx(4.0).epsilon(1e-12));
  // u = 1/4: h00 = 0.84375, h10 = 0.140625, h01 = 0.15625, h11 = -0.046875.
  CHECK(cr::sample_values(s, 0.5)[0] == doctest::Approx(0.84375 + 2 * 0.140625 * 3 + 0.15625 * 5 + 2 * 0.046875).epsilon(1e-12));
  // Rotations from a spline are normalised: with zero tangents, halfway
  // between identity and 90 degrees about Z is the normalised mean, 45 degrees.
  const float s45 = std::sqrt(0.5f);
  const cr::AnimationSampler r = sampler(cr::Interpolation::CubicSpline, {0, 1},
                                         {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,      // key 0: in, identity, out
                                          0, 0, 0, 0, 0, 0, s45, s45, 0, 0, 0, 0},  // key 1: in, 90 about Z, out
                                         4);
  CHECK(glm::length(cr::sample_rotation(r, 0.5)) == doctest::Approx(1.0));
  CHECK(angle_between(cr::sample_rotation(r, 0.5), glm::angleAxis(glm::radians(45.0), glm::dvec3(0, 0, 1))) < 1e-6);
}

TEST_CASE("LINEAR rotations are slerped along the shorter arc") {
  const glm::dquat quarter = glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 1, 0));
  for (double sign : {1.0, -1.0}) {  // q and -q are the same rotation
    CAPTURE(sign);
    const glm::dquat q = sign * quarter;
    const cr::AnimationSampler s = sampler(cr::Interpolation::Linear, {0, 1},
                                           {0, 0, 0, 1, float(q.x), float(q.y), float(q.z), float(q.w)}, 4);
    CHECK(angle_between(cr::sample_rotation(s, 0.5), glm::angleAxis(glm::radians(45.0), glm::dvec3(0, 1, 0))) < 1e-6);
    CHECK(angle_between(cr::sample_rotation(s, 0.25), glm::angleAxis(glm::radians(22.5), glm::dvec3(0, 1, 0))) < 1e-6);
    CHECK(glm::length(cr::sample_rotation(s, 0.3)) == doctest::Approx(1.0));
  }
}

TEST_CASE("node translation, rotation and scale channels pose the scene; rest again without animation") {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.add("nodes", {{"translation", {0.0, 0.0, -1.0}}, {"children", {1}}});
  b.add("nodes", {{"mesh", 0}, {"translation", {1.0, 0.0, 0.0}}});
  int times = b.floats({0, 2}, "SCALAR", 1);
  int translations = b.floats({0, 0, 0, 4, 0, 0}, "VEC3", 3);
  const glm::quat turn = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  int rotations = b.floats({0, 0, 0, 1, turn.x, turn.y, turn.z, turn.w}, "VEC4", 4);
  int scales = b.floats({1, 1, 1, 3, 3, 3}, "VEC3", 3);
  b.add("animations", {{"name", "slide"},
                       {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                                     {{"sampler", 1}, {"target", {{"node", 0}, {"path", "rotation"}}}},
                                     {{"sampler", 2}, {"target", {{"node", 1}, {"path", "scale"}}}}}},
                       {"samplers", {{{"input", times}, {"output", translations}},
                                     {{"input", times}, {"output", rotations}},
                                     {{"input", times}, {"output", scales}, {"interpolation", "STEP"}}}}});
  const std::string path = b.write("node_channels.gltf");
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.animation != nullptr);
  REQUIRE(s.animation->animations.size() == 1);
  CHECK(s.animation->animations[0].duration_s == 2.0);
  const glm::mat4 rest = s.draws.at(0).world;
  CHECK(rest == glm::translate(glm::mat4(1.0f), glm::vec3(1, 0, -1)));

  cr::pose_scene(s, *s.animation, 0, 1.0);
  // Parent: T(0,0,-1) * Rz(45); child: T(2,0,0) * S(1) (STEP holds the first scale).
  const glm::mat4 expected = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -1)) *
                             glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(0, 0, 1)) *
                             glm::translate(glm::mat4(1.0f), glm::vec3(2, 0, 0));
  for (int c = 0; c < 4; ++c) CHECK(glm::length(s.draws[0].world[c] - expected[c]) < 1e-6f);
  const glm::vec3 o(s.draws[0].world[3]);
  CHECK(glm::all(glm::greaterThanEqual(o, s.bounds_min - 1e-6f)));  // bounds follow the pose
  // The triangle's vertex (1, 0, 0) sits at (3, 0, 0) in the parent, turned 45 degrees.
  CHECK(s.bounds_max.x == doctest::Approx(3.0 / std::sqrt(2.0)).epsilon(1e-6));

  cr::pose_scene(s, *s.animation, 0, 2.0);
  CHECK(glm::length(glm::vec3(s.draws[0].world[0]) - glm::vec3(0, 3, 0)) < 1e-5f);  // scaled 3, turned 90

  cr::pose_scene(s, *s.animation, std::nullopt, 0.0);
  CHECK(s.draws[0].world == rest);
}

TEST_CASE("a node scaled to zero by an animation is not drawn at that time") {
  const std::string path = animated_file("anim_scale_to_zero.gltf", [](GltfBuilder& b) {
    return one_channel("scale", b.floats({0, 1}, "SCALAR", 1), b.floats({1, 1, 1, 0, 0, 0}, "VEC3", 3));
  });
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.draws.size() == 1);
  CHECK(cr::pose_scene(s, *s.animation, 0, 0.5) == 0);
  CHECK(s.draws.size() == 1);
  CHECK(cr::pose_scene(s, *s.animation, 0, 1.0) == 1);
  CHECK(s.draws.empty());
  CHECK(s.bounds_min == glm::vec3(0.0f));
  CHECK(s.bounds_max == glm::vec3(0.0f));
}

TEST_CASE("CesiumMilkTruck's animation turns the wheels about their axles and leaves the body (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("khronos/CesiumMilkTruck/glTF/CesiumMilkTruck.gltf");
  if (!found) return;
  const std::string& path = *found;
  cr::Scene s = cr::load_gltf(path);
  REQUIRE(s.animation != nullptr);
  REQUIRE(s.animation->animations.size() == 1);
  CHECK(s.animation->animations[0].name == "Wheels");
  CHECK(s.animation->animations[0].duration_s == doctest::Approx(1.25));
  const std::vector<cr::Draw> rest = s.draws;
  REQUIRE(rest.size() == 5);  // three body primitives, two wheels
  cr::pose_scene(s, *s.animation, 0, 0.125);  // key 3
  REQUIRE(s.draws.size() == rest.size());
  int wheels = 0;
  for (size_t i = 0; i < rest.size(); ++i) {
    CAPTURE(i);
    const glm::mat4 &a = rest[i].world, &b = s.draws[i].world;
    if (rest[i].mesh != 0) {
      CHECK(a == b);  // the body is not animated
      continue;
    }
    ++wheels;
    CHECK(glm::length(a[3] - b[3]) < 1e-6f);                              // the hub stays
    CHECK(glm::length(glm::normalize(a[1]) - glm::normalize(b[1])) < 1e-5f);  // the axle (local Y) stays
    // The wheel turned by the angle between key 0 and key 3 of its sampler.
    const double expected = 2.0 * std::acos(0.0884859040 * 0.3837876916 + 0.9960774183 * 0.9234213829);
    const double turned = std::acos(glm::dot(glm::normalize(glm::vec3(a[0])), glm::normalize(glm::vec3(b[0]))));
    CHECK(turned == doctest::Approx(expected).epsilon(1e-4));
  }
  CHECK(wheels == 2);
}

TEST_CASE("the scene file's animation key chooses the animation by index or name") {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.add("nodes", {{"mesh", 0}});
  int times = b.floats({0, 1}, "SCALAR", 1);
  int up = b.floats({0, 0, 0, 0, 10, 0}, "VEC3", 3);
  int side = b.floats({0, 0, 0, 10, 0, 0}, "VEC3", 3);
  for (auto [name, output] : {std::pair{"up", up}, std::pair{"side", side}}) {
    b.add("animations", {{"name", name},
                         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                         {"samplers", {{{"input", times}, {"output", output}}}}});
  }
  cr::Scene s = cr::load_gltf(b.write("two_animations.gltf"));
  cr::SceneDescription d;
  d.path = "scene.json";
  auto spec = [](std::optional<int> index, const std::string& name, double time_s) {
    cr::AnimationSpec a;
    a.index = index;
    a.name = name;
    a.time_s = time_s;
    return a;
  };
  CHECK_FALSE(cr::described_animation(s, d).has_value());
  cr::pose_described_scene(s, d);  // the rest pose, with a warning naming both animations
  CHECK(glm::vec3(s.draws.at(0).world[3]) == glm::vec3(0.0f));

  d.animation = spec(std::nullopt, "side", 0.5);
  CHECK(cr::described_animation(s, d) == 1u);
  cr::pose_described_scene(s, d);
  CHECK(glm::vec3(s.draws.at(0).world[3]) == glm::vec3(5, 0, 0));
  d.animation = spec(0, "", 2.0);
  cr::pose_described_scene(s, d);
  CHECK(glm::vec3(s.draws.at(0).world[3]) == glm::vec3(0, 10, 0));

  auto error_of = [&](cr::AnimationSpec spec) {
    d.animation = spec;
    try {
      cr::described_animation(s, d);
    } catch (const cr::InputError& e) {
      CHECK(e.file() == "scene.json");
      return std::string(e.what());
    }
    FAIL("expected InputError");
    return std::string();
  };
  CHECK(error_of(spec(2, "", 0.0)).find("'animation.index' is 2 but") != std::string::npos);
  const std::string missing = error_of(spec(std::nullopt, "jump", 0.0));
  CHECK(missing.find("'animation.name' is \"jump\"") != std::string::npos);
  CHECK(missing.find("2 animation(s): \"up\", \"side\"") != std::string::npos);
}

TEST_CASE("malformed animations are rejected with one clear error") {
  auto translation = [](std::vector<float> times, std::vector<float> values, const char* interpolation = "LINEAR",
                        const char* path = "translation", const char* type = "VEC3", size_t components = 3) {
    return [=](GltfBuilder& b) {
      int in = b.floats(times, "SCALAR", 1);
      int out = b.floats(values, type, components);
      return one_channel(path, in, out, interpolation);
    };
  };
  expect_gltf_rejected(animated_file("anim_nan_key.gltf", translation({0, 1}, {0, 0, 0, 1, NAN, 0})),
                       "animation 0 channel 0 sampler 0 output value 4 is not finite");
  expect_gltf_rejected(animated_file("anim_nan_time.gltf", translation({0, NAN}, {0, 0, 0, 1, 1, 0})),
                       "input: time 1 is not finite");
  expect_gltf_rejected(animated_file("anim_times_not_increasing.gltf", translation({0, 1, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0})),
                       "time 2 (1.000000 s) does not follow time 1 (1.000000 s); times must be strictly increasing");
  expect_gltf_rejected(animated_file("anim_negative_time.gltf", translation({-1, 1}, {0, 0, 0, 1, 0, 0})),
                       "times must be >= 0");
  expect_gltf_rejected(animated_file("anim_output_count.gltf", translation({0, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0})),
                       "output has 3 elements; expected 2 (2 keys)");
  expect_gltf_rejected(animated_file("anim_cubic_count.gltf", translation({0, 1}, {0, 0, 0, 1, 0, 0}, "CUBICSPLINE")),
                       "output has 2 elements; expected 6 (2 keys x 3 for CUBICSPLINE)");
  expect_gltf_rejected(animated_file("anim_interpolation.gltf", translation({0, 1}, {0, 0, 0, 1, 0, 0}, "SMOOTH")),
                       "has interpolation \"SMOOTH\"; expected LINEAR, STEP or CUBICSPLINE");
  expect_gltf_rejected(animated_file("anim_rotation_type.gltf", translation({0, 1}, {0, 0, 0, 1, 0, 0}, "LINEAR", "rotation")),
                       "expected VEC4");
  expect_gltf_rejected(animated_file("anim_zero_rotation.gltf",
                                     translation({0, 1}, {0, 0, 0, 1, 0, 0, 0, 0}, "LINEAR", "rotation", "VEC4", 4)),
                       "output rotation of key 1 is a zero quaternion");
  expect_gltf_rejected(animated_file("anim_weights_no_targets.gltf",
                                     translation({0, 1}, {0, 1}, "LINEAR", "weights", "SCALAR", 1)),
                       "animates morph weights but the node has no mesh with morph targets");
  expect_gltf_rejected(animated_file("anim_node_out_of_range.gltf", [](GltfBuilder& b) {
                         return one_channel("translation", b.floats({0}, "SCALAR", 1), b.floats({0, 0, 0}, "VEC3", 3),
                                            "LINEAR", 7);
                       }),
                       "animation 0 channel 0 target node 7 out of range (1 nodes)");
  expect_gltf_rejected(animated_file("anim_sampler_out_of_range.gltf", [](GltfBuilder& b) {
                         nlohmann::json a = one_channel("translation", b.floats({0}, "SCALAR", 1), b.floats({0, 0, 0}, "VEC3", 3));
                         a["channels"][0]["sampler"] = 4;
                         return a;
                       }),
                       "channel 0 sampler 4 out of range (1 samplers)");
  expect_gltf_rejected(animated_file("anim_duplicate_target.gltf", [](GltfBuilder& b) {
                         nlohmann::json a = one_channel("translation", b.floats({0}, "SCALAR", 1), b.floats({0, 0, 0}, "VEC3", 3));
                         a["channels"].push_back(a["channels"][0]);
                         return a;
                       }),
                       "channel 1 (node 0 translation) animates a property another channel of the animation already animates");
  {
    GltfBuilder b;
    b.add("nodes", {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
    b.add("animations", one_channel("scale", b.floats({0}, "SCALAR", 1), b.floats({1, 1, 1}, "VEC3", 3)));
    expect_gltf_rejected(b.write("anim_matrix_node.gltf"), "animates a node given by \"matrix\"");
  }
  // Paths left to extensions are ignored, with a warning.
  cr::Scene ignored = cr::load_gltf(animated_file("anim_pointer_path.gltf", [](GltfBuilder& b) {
    return one_channel("pointer", b.floats({0}, "SCALAR", 1), b.floats({5, 0, 0}, "VEC3", 3));
  }));
  REQUIRE(ignored.animation != nullptr);
  CHECK(ignored.animation->animations.at(0).channels.empty());
}

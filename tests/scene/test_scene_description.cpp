// Scene files: every form of camera and sun, plugin sections, strictness.
#include <filesystem>
#include <fstream>
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/scene_description.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

const std::string kBadScenes = std::string(CR_TEST_DATA_DIR) + "/bad";
const std::vector<std::string> kPlugins = {"atmosphere", "fog"};

// Writes a scene file next to a valid glTF path ("box.gltf" in the same directory).
std::string write_scene(const std::string& name, nlohmann::json doc) {
  std::string dir = cr::test::test_output_dir();
  std::ofstream(dir + "/scene_box.gltf") << R"({"asset": {"version": "2.0"}})";
  std::string path = dir + "/" + name;
  std::ofstream(path) << doc.dump(1);
  return path;
}

std::string error_of(const std::string& path) {
  try {
    cr::load_scene_description(path, kPlugins);
  } catch (const cr::InputError& e) {
    CHECK(e.file() == path);
    return e.what();
  }
  FAIL("expected InputError for " << path);
  return "";
}

}  // namespace

TEST_CASE("a bare glTF path is a scene: camera and sun from the glTF") {
  const std::string gltf = std::string(CR_ASSIMP_GLTF_DIR) + "/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(gltf)) return;
  cr::SceneDescription d = cr::load_scene_description(gltf, kPlugins);
  CHECK(d.gltf_path == gltf);
  CHECK(d.path == gltf);
  CHECK(d.camera.keys.empty());
  CHECK_FALSE(d.camera.gltf_camera.has_value());
  CHECK(d.sun.from_gltf);
  CHECK(d.plugins.empty());
  CHECK_THROWS_AS(cr::load_scene_description(kBadScenes + "/does_not_exist.glb", kPlugins), cr::InputError);
}

TEST_CASE("scene file with a static camera, a fixed sun and plugin sections") {
  std::string path = write_scene("static.json", {
      {"gltf", "scene_box.gltf"},
      {"camera", {{"position", {1, 2, 3}}, {"target", {0, 1, 0}}, {"vfov_deg", 45}, {"znear", 0.5}}},
      {"sun", {{"azimuth_deg", 30}, {"elevation_deg", -5}, {"illuminance", 90000}, {"color", {1.0, 0.9, 0.8}}}},
      {"exposure_ev100", 12.5},
      {"ambient", {0.1, 0.2, 0.3}},
      {"frames", 24},
      {"atmosphere", {{"anything", "the plugin validates this"}}},
  });
  cr::SceneDescription d = cr::load_scene_description(path, kPlugins);
  CHECK(std::filesystem::equivalent(d.gltf_path, cr::test::test_output_dir() + "/scene_box.gltf"));
  REQUIRE(d.camera.keys.size() == 1);
  CHECK(d.camera.keys[0].frame == 0);
  CHECK(d.camera.keys[0].position == glm::dvec3(1, 2, 3));
  CHECK(d.camera.keys[0].target == glm::dvec3(0, 1, 0));
  CHECK(d.camera.keys[0].vfov_deg == 45.0f);
  CHECK(d.camera.znear == 0.5f);
  REQUIRE(d.sun.keys.size() == 1);
  CHECK(d.sun.keys[0].azimuth_deg == 30.0f);
  CHECK(d.sun.keys[0].elevation_deg == -5.0f);
  CHECK_FALSE(d.sun.from_gltf);
  CHECK(d.sun.illuminance == 90000.0f);
  CHECK(d.sun.color == glm::vec3(1.0f, 0.9f, 0.8f));
  CHECK(d.exposure_ev100 == 12.5f);
  CHECK(d.ambient == glm::vec3(0.1f, 0.2f, 0.3f));
  CHECK(d.frames == 24);
  CHECK(d.plugins.contains("atmosphere"));
  CHECK(d.plugins["atmosphere"]["anything"] == "the plugin validates this");
  CHECK_FALSE(d.plugins.contains("fog"));
}

TEST_CASE("scene file with camera and sun keys, and with a glTF camera and sun") {
  std::string keyed = write_scene("keyed.json", {
      {"gltf", "scene_box.gltf"},
      {"camera", {{"keys", {{{"frame", 0}, {"position", {0, 0, 5}}, {"target", {0, 0, 0}}},
                            {{"frame", 10}, {"position", {5, 0, 0}}, {"target", {0, 0, 0}}, {"cut", true}, {"vfov_deg", 30}}}}}},
      {"sun", {{"keys", {{{"frame", 0}, {"azimuth_deg", 0}, {"elevation_deg", 10}},
                         {{"frame", 5}, {"azimuth_deg", 90}, {"elevation_deg", 60}}}}}},
  });
  cr::SceneDescription d = cr::load_scene_description(keyed, kPlugins);
  REQUIRE(d.camera.keys.size() == 2);
  CHECK(d.camera.keys[1].frame == 10);
  CHECK(d.camera.keys[1].cut);
  CHECK_FALSE(d.camera.keys[0].cut);
  CHECK(d.camera.keys[0].vfov_deg == 60.0f);  // default
  REQUIRE(d.sun.keys.size() == 2);
  CHECK(d.sun.keys[1].elevation_deg == 60.0f);

  std::string from_gltf = write_scene("from_gltf.json", {
      {"gltf", "scene_box.gltf"}, {"camera", {{"gltf_camera", 2}}}, {"sun", {{"from_gltf", true}, {"illuminance", 5}}}});
  cr::SceneDescription g = cr::load_scene_description(from_gltf, kPlugins);
  CHECK(g.camera.gltf_camera == 2);
  CHECK(g.sun.from_gltf);
  CHECK(g.sun.illuminance == 5.0f);
}

TEST_CASE("scene file errors name the file and the field") {
  CHECK(error_of(kBadScenes + "/scene_unknown_key.json").find("unknown key 'sunn'") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_bad_vfov.json").find("camera.vfov_deg") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_keys_not_increasing.json").find("camera.keys[1].frame") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_missing_gltf.json").find("'gltf'") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_bad_elevation.json").find("sun.elevation_deg") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_malformed.json").find("line 3") != std::string::npos);
  CHECK(error_of(kBadScenes + "/scene_deep_plugin.json").find("more than 128 levels deep") != std::string::npos);

  CHECK(error_of(write_scene("no_gltf.json", {{"frames", 2}})).find("'gltf' is required") != std::string::npos);
  CHECK(error_of(write_scene("nested_unknown.json", {{"gltf", "scene_box.gltf"},
                                                     {"camera", {{"position", {0, 0, 1}}, {"target", {0, 0, 0}}, {"fov", 3}}}}))
            .find("'camera.fov'") != std::string::npos);
  CHECK(error_of(write_scene("zero_frames.json", {{"gltf", "scene_box.gltf"}, {"frames", 0}})).find("'frames'") !=
        std::string::npos);
  CHECK(error_of(write_scene("znear.json", {{"gltf", "scene_box.gltf"},
                                            {"camera", {{"position", {0, 0, 1}}, {"target", {0, 0, 0}}, {"znear", 0}}}}))
            .find("'camera.znear'") != std::string::npos);
  CHECK(error_of(write_scene("same_pos_target.json", {{"gltf", "scene_box.gltf"},
                                                      {"camera", {{"position", {0, 0, 0}}, {"target", {0, 0, 0}}}}}))
            .find("'camera.target'") != std::string::npos);
  CHECK(error_of(write_scene("bad_ambient.json", {{"gltf", "scene_box.gltf"}, {"ambient", {0, -1, 0}}})).find("'ambient'") !=
        std::string::npos);
  CHECK(error_of(write_scene("not_object.json", nlohmann::json::array({1, 2}))).find("JSON object") != std::string::npos);
}

TEST_CASE("scene file animation key: by index or name, with a time; strict") {
  cr::SceneDescription none = cr::load_scene_description(write_scene("no_animation.json", {{"gltf", "scene_box.gltf"}}), kPlugins);
  CHECK_FALSE(none.animation.has_value());  // the rest pose

  cr::SceneDescription by_index = cr::load_scene_description(
      write_scene("animation_index.json", {{"gltf", "scene_box.gltf"}, {"animation", {{"index", 2}, {"time", 1.25}}}}), kPlugins);
  REQUIRE(by_index.animation.has_value());
  CHECK(by_index.animation->index == 2);
  CHECK(by_index.animation->time_s == 1.25);
  CHECK_FALSE(by_index.animation->fps.has_value());  // a still pose on every frame
  CHECK(by_index.animation->time_at(7) == 1.25);
  const cr::SceneDescription playing = cr::load_scene_description(
      write_scene("animation_fps.json", {{"gltf", "scene_box.gltf"}, {"animation", {{"index", 0}, {"time", 0.5}, {"fps", 4}}}}),
      kPlugins);
  CHECK(playing.animation->time_at(6) == 0.5 + 6.0 / 4.0);

  cr::SceneDescription by_name = cr::load_scene_description(
      write_scene("animation_name.json", {{"gltf", "scene_box.gltf"}, {"animation", {{"name", "Walk"}}}}), kPlugins);
  REQUIRE(by_name.animation.has_value());
  CHECK_FALSE(by_name.animation->index.has_value());
  CHECK(by_name.animation->name == "Walk");
  CHECK(by_name.animation->time_s == 0.0);

  auto bad = [](const char* file, nlohmann::json animation) {
    return error_of(write_scene(file, {{"gltf", "scene_box.gltf"}, {"animation", std::move(animation)}}));
  };
  CHECK(bad("animation_both.json", {{"index", 0}, {"name", "Walk"}}).find("exactly one of") != std::string::npos);
  CHECK(bad("animation_neither.json", {{"time", 1.0}}).find("exactly one of") != std::string::npos);
  CHECK(bad("animation_unknown.json", {{"index", 0}, {"speed", 2}}).find("'animation.speed'") != std::string::npos);
  CHECK(bad("animation_negative_time.json", {{"index", 0}, {"time", -1}}).find("'animation.time'") != std::string::npos);
  CHECK(bad("animation_negative_index.json", {{"index", -1}}).find("'animation.index'") != std::string::npos);
  CHECK(bad("animation_zero_fps.json", {{"index", 0}, {"fps", 0}}).find("'animation.fps'") != std::string::npos);
  CHECK(bad("animation_name_number.json", {{"name", 3}}).find("'animation.name'") != std::string::npos);
  CHECK(bad("animation_not_object.json", 3).find("'animation'") != std::string::npos);
}

// Found by fuzz_scene: a 'gltf' name longer than a file name may be made
// std::filesystem throw filesystem_error ("File name too long") past the loader.
TEST_CASE("a scene whose gltf name cannot be looked up says the file does not exist") {
  const std::string path = kBadScenes + "/fuzz_scene_gltf_name_too_long.json";
  CHECK(error_of(path).find(path + ": 'gltf' names a file that does not exist (looked for ") == 0);
  const std::string too_long = write_scene("long_name.json", {{"gltf", std::string(5000, 'a') + ".glb"}});
  CHECK(error_of(too_long).find("'gltf' names a file that does not exist") != std::string::npos);
  const std::string through_file = write_scene("through_file.json", {{"gltf", "scene_box.gltf/inner.glb"}});
  CHECK(error_of(through_file).find("'gltf' names a file that does not exist") != std::string::npos);
}

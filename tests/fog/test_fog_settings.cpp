#include <doctest/doctest.h>

#include <string>

#include "engine/core/error.h"
#include "fog/fog_plugin.h"
#include "fog/fog_settings.h"

using namespace cr;
using nlohmann::json;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("profile fog section: defaults and values") {
  const FogProfileSettings d = parse_fog_profile(json::object(), "p.json");
  CHECK(d.froxel_size_px == 8);
  CHECK(d.slices == 64);
  CHECK(d.fog_distance == 64.0f);
  CHECK(d.slice_uniformity == 0.75f);
  CHECK(d.history_weight == doctest::Approx(6.0 / 7.0));
  CHECK(d.filter);
  CHECK(d.density_samples == 4);
  CHECK(d.jitter);
  CHECK(d.reprojection);
  const FogProfileSettings s = parse_fog_profile(
      json{{"froxel_size_px", 16}, {"slices", 32}, {"fog_distance", 100}, {"reprojection", false}}, "p.json");
  CHECK(s.froxel_size_px == 16);
  CHECK(s.slices == 32);
  CHECK(s.fog_distance == 100.0f);
  CHECK_FALSE(s.reprojection);
  CHECK(d.precision == FogPrecision::Float);
  CHECK(parse_fog_profile(json{{"precision", "fixed"}}, "p.json").precision == FogPrecision::Fixed);
  CHECK(parse_fog_profile(json{{"precision", "float"}}, "p.json").precision == FogPrecision::Float);
}

TEST_CASE("profile fog section: bad input names file and field") {
  CHECK(error_of([] { parse_fog_profile(json{{"slice", 3}}, "p.json"); }).find("p.json: unknown key 'fog.slice'") == 0);
  CHECK(error_of([] { parse_fog_profile(json{{"slices", 0}}, "p.json"); }).find("'fog.slices'") != std::string::npos);
  CHECK(error_of([] { parse_fog_profile(json{{"history_weight", 1.0}}, "p.json"); }).find("'fog.history_weight'") !=
        std::string::npos);
  CHECK(error_of([] { parse_fog_profile(json{{"density_samples", 0}}, "p.json"); }).find("'fog.density_samples'") !=
        std::string::npos);
  CHECK(error_of([] { parse_fog_profile(json{{"filter", "yes"}}, "p.json"); }).find("'fog.filter'") !=
        std::string::npos);
  CHECK(error_of([] { parse_fog_profile(json::array(), "p.json"); }).find("p.json") == 0);
  const std::string precision = error_of([] { parse_fog_profile(json{{"precision", "half"}}, "p.json"); });
  CHECK(precision.find("p.json") == 0);
  CHECK(precision.find("'fog.precision'") != std::string::npos);
  CHECK(precision.find("\"half\"") != std::string::npos);
  CHECK(error_of([] { parse_fog_profile(json{{"precision", 16}}, "p.json"); }).find("'fog.precision'") !=
        std::string::npos);
}

TEST_CASE("scene fog section: height fog, volumes, phase") {
  const json j = json::parse(R"({
    "height_fog": {"base_height": 2, "max_height": 32, "mean_free_path": 25, "albedo": [0.9, 0.8, 0.7]},
    "volumes": [
      {"center": [0, 1, -10], "size": [4, 2, 6], "rotation_deg": [0, 90, 0], "mean_free_path": 2,
       "blend": "max", "fade": 0.5, "noise": {"scale": 3, "octaves": 2}},
      {"center": [5, 1, -10], "size": [1, 1, 1], "axes": [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], "mean_free_path": 4}
    ],
    "phase": "cornette-shanks", "anisotropy": 0.6})");
  const FogSceneSettings s = parse_fog_scene(j, "s.json");
  CHECK(s.height_fog);
  CHECK(s.base_height == 2.0f);
  CHECK(s.extinction == doctest::Approx(0.04f));
  CHECK(s.albedo.y == doctest::Approx(0.8f));
  REQUIRE(s.volumes.size() == 2);
  CHECK(s.volumes[0].blend == FogBlend::Max);
  CHECK(s.volumes[0].half_size.z == 3.0f);
  CHECK(s.volumes[0].extinction == 0.5f);
  CHECK(s.volumes[0].noise.enabled);
  CHECK(s.volumes[0].noise.octaves == 2);
  // Yaw 90 degrees maps the box's x axis to world -z.
  CHECK(s.volumes[0].axes[0].z == doctest::Approx(-1.0f));
  CHECK(s.volumes[1].blend == FogBlend::Additive);
  CHECK(s.volumes[1].axes[0].z == 1.0f);
  CHECK(s.phase == FogPhase::CornetteShanks);
  CHECK(s.anisotropy == doctest::Approx(0.6f));
}

TEST_CASE("scene fog section: bad input names file and field") {
  auto err = [](const char* text) { return error_of([&] { parse_fog_scene(json::parse(text), "s.json"); }); };
  CHECK(err(R"({"heightfog": {}})").find("unknown key 'fog.heightfog'") != std::string::npos);
  CHECK(err(R"({"height_fog": {"mean_free_path": 0}})").find("'fog.height_fog.mean_free_path'") != std::string::npos);
  // Valid as a number, but its extinction 1 / mfp would overflow a float.
  CHECK(err(R"({"height_fog": {"mean_free_path": 1e-45}})").find("'fog.height_fog.mean_free_path'") != std::string::npos);
  CHECK(err(R"({"volumes": [{"center": [0,0,0], "size": [1,1,1], "mean_free_path": 1e-4}]})")
            .find("'fog.volumes[0].mean_free_path'") != std::string::npos);
  CHECK(err(R"({"height_fog": {"mean_free_path": 5, "base_height": 10, "max_height": 5}})")
            .find("'fog.height_fog.max_height'") != std::string::npos);
  CHECK(err(R"({"volumes": [{"center": [0,0,0], "size": [1,1,1], "mean_free_path": 1, "blend": "screen"}]})")
            .find("'fog.volumes[0].blend'") != std::string::npos);
  CHECK(err(R"({"volumes": [{"center": [0,0,0], "size": [1,-1,1], "mean_free_path": 1}]})")
            .find("'fog.volumes[0].size'") != std::string::npos);
  CHECK(err(R"({"volumes": [{"center": [0,0,0], "size": [1,1,1], "mean_free_path": 1,
                "axes": [[1,0,0],[1,0,0],[0,0,1]]}]})")
            .find("'fog.volumes[0].axes'") != std::string::npos);
  CHECK(err(R"({"phase": "rayleigh"})").find("'fog.phase'") != std::string::npos);
  CHECK(err(R"({"anisotropy": 1.0})").find("'fog.anisotropy'") != std::string::npos);
  CHECK(err(R"({"volumes": [{"center": [0,0,0], "size": [1,1,1], "mean_free_path": 1, "noise": {"octave": 2}}]})")
            .find("'fog.volumes[0].noise.octave'") != std::string::npos);
}

TEST_CASE("zero-size volumes and an empty volume list are valid") {
  const FogSceneSettings s = parse_fog_scene(
      json::parse(R"({"volumes": [{"center": [0,0,0], "size": [0,0,0], "mean_free_path": 1}]})"), "s.json");
  CHECK(s.volumes.size() == 1);
  CHECK(parse_fog_scene(json::parse(R"({"volumes": []})"), "s.json").volumes.empty());
}

TEST_CASE("the plugin: no fog section means no passes; bad profile sections are reported anyway") {
  FogPlugin plugin;
  Scene scene;
  SceneDescription d;
  d.path = "s.json";
  Profile p;
  p.path = "p.json";
  CHECK(plugin.name() == "fog");
  CHECK_FALSE(plugin.configure(scene, d, p));
  p.plugins["fog"] = json{{"slices", -1}};
  CHECK(error_of([&] { plugin.configure(scene, d, p); }).find("'fog.slices'") != std::string::npos);
  p.plugins["fog"] = json{{"slices", 16}};
  d.plugins["fog"] = json::parse(R"({"height_fog": {"mean_free_path": 30}, "distance": 100})");
  CHECK(plugin.configure(scene, d, p));
  CHECK(plugin.fog()->profile().slices == 16);
  CHECK(plugin.fog()->profile().fog_distance == 100.0f);  // the scene's distance wins
  CHECK(plugin.composite_order() == 200);
}

// The command line's --camera, --sun, --sky and --exposure on a loaded
// scene description, and their malformed values.
#include <doctest/doctest.h>

#include "engine/cli/scene_overrides.h"

namespace {

cr::SceneOverrides parse(std::vector<std::string> args) {
  cr::ArgParser p("render", "render [SCENE]", "");
  cr::add_scene_override_options(p);
  p.parse(args, 0, 1);
  return cr::parse_scene_overrides(p, "render");
}

}  // namespace

TEST_CASE("scene overrides replace the view, the sun, the sky preset and the exposure") {
  cr::SceneDescription d;
  d.camera.keys.push_back(cr::CameraKey{});
  d.sun.from_gltf = true;
  d.plugins["atmosphere"] = {{"preset", "earth-clear"}, {"ground_altitude_m", 10}};
  cr::apply_scene_overrides(parse({"--camera", "auto", "--sun", "12.5,-30", "--sky", "mars-like", "--exposure", "9"}), d);
  CHECK(d.camera.auto_frame);
  CHECK(d.camera.keys.empty());
  CHECK_FALSE(d.sun.from_gltf);
  REQUIRE(d.sun.keys.size() == 1);
  CHECK(d.sun.keys[0].elevation_deg == 12.5f);
  CHECK(d.sun.keys[0].azimuth_deg == -30.0f);
  CHECK(d.plugins["atmosphere"]["preset"] == "mars-like");
  CHECK(d.plugins["atmosphere"]["ground_altitude_m"] == 10);  // the scene's other keys stay
  CHECK(d.exposure_ev100 == 9.0f);

  cr::apply_scene_overrides(parse({"--camera", "1"}), d);
  CHECK_FALSE(d.camera.auto_frame);
  CHECK(d.camera.gltf_camera == 1);

  cr::SceneDescription bare;  // a scene without an atmosphere section gets one
  cr::apply_scene_overrides(parse({"--sky", "earth-hazy"}), bare);
  CHECK(bare.plugins["atmosphere"] == nlohmann::json{{"preset", "earth-hazy"}});
  CHECK(bare.camera.keys.empty());  // untouched without --camera
}

TEST_CASE("scene overrides: malformed values are usage errors naming the option") {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"--camera", "front"}, {"--camera", "-1"}, {"--sun", "45"}, {"--sun", "95,0"}, {"--sun", "10,20,30"},
           {"--sun", "nan,0"}, {"--exposure", "high"}, {"--exposure", "99"}, {"--sky", ""}}) {
    CAPTURE(args[1]);
    try {
      parse(args);
      FAIL("expected UsageError");
    } catch (const cr::UsageError& e) {
      CHECK(std::string(e.what()).find(args[0]) != std::string::npos);
    }
  }
}

#include "engine/cli/scene_overrides.h"

#include <cmath>
#include <cstdio>

namespace cr {

void add_scene_override_options(ArgParser& p) {
  p.option("camera", "auto|N", "view: 'auto' (three-quarter view fitting the model) or the glTF's camera N")
      .option("sun", "EL,AZ", "one fixed sun: elevation and azimuth in degrees (azimuth clockwise from +Z to +X)")
      .option("sky", "PRESET", "render under the physical sky: an atmosphere preset (e.g. earth-clear)")
      .option("exposure", "EV100", "photographic exposure (white = 1.2 * 2^EV100 cd/m^2)");
}

SceneOverrides parse_scene_overrides(const ArgParser& p, const std::string& command) {
  SceneOverrides o;
  if (p.has("camera")) {
    const std::string c = p.get("camera");
    if (c != "auto") p.get_int("camera", 0, 1 << 20);  // throws UsageError unless an index
    o.camera = c;
  }
  if (p.has("sun")) {
    const std::string s = p.get("sun");
    float el = 0.0f, az = 0.0f;
    char tail = 0;
    if (std::sscanf(s.c_str(), "%f,%f%c", &el, &az, &tail) != 2 || !std::isfinite(el) || !std::isfinite(az) ||
        el < -90.0f || el > 90.0f || az < -360.0f || az > 360.0f)
      throw UsageError(command + ": --sun expects ELEVATION,AZIMUTH in degrees (elevation in [-90, 90], azimuth in "
                       "[-360, 360]), got '" + s + "'");
    o.sun = {el, az};
  }
  if (p.has("sky")) {
    o.sky = p.get("sky");
    if (o.sky->empty()) throw UsageError(command + ": --sky expects an atmosphere preset name");
  }
  if (p.has("exposure")) o.exposure_ev100 = float(p.get_double("exposure", -30.0, 40.0));
  return o;
}

void apply_scene_overrides(const SceneOverrides& o, SceneDescription& d) {
  if (o.camera) {
    d.camera.keys.clear();
    d.camera.gltf_camera.reset();
    d.camera.auto_frame = *o.camera == "auto";
    if (!d.camera.auto_frame) d.camera.gltf_camera = std::stoi(*o.camera);
  }
  if (o.sun) {
    d.sun.from_gltf = false;
    d.sun.keys = {SunKey{0, o.sun->second, o.sun->first}};
  }
  if (o.sky) {
    nlohmann::json& section = d.plugins["atmosphere"];
    if (!section.is_object()) section = nlohmann::json::object();
    section["preset"] = *o.sky;  // the plugin validates the name
  }
  if (o.exposure_ev100) d.exposure_ev100 = *o.exposure_ev100;
}

}  // namespace cr

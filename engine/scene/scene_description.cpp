#include "engine/scene/scene_description.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace cr {

namespace {

namespace fs = std::filesystem;

const NumberRange kAnyFinite{-1e30, 1e30};
const NumberRange kNonNegative{0.0, 1e30};
const NumberRange kVfov{0.0, 180.0, true, true};
const NumberRange kZnear{0.0, 1e30, true};
const NumberRange kElevation{-90.0, 90.0};
const NumberRange kAzimuth{-360.0, 360.0};
constexpr int kMaxFrames = 1000000;

bool has_gltf_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".gltf" || ext == ".glb";
}

CameraKey parse_camera_key(const JsonObject& o, bool with_frame) {
  CameraKey k;
  if (with_frame) k.frame = o.integer("frame", 0, kMaxFrames);
  k.position = o.vec3("position", kAnyFinite);
  k.target = o.vec3("target", kAnyFinite);
  if (k.position == k.target) o.fail("target", "must differ from 'position' (no view direction)");
  if (o.has("vfov_deg")) k.vfov_deg = static_cast<float>(o.number("vfov_deg", kVfov));
  if (with_frame && o.has("cut")) k.cut = o.boolean("cut");
  return k;
}

CameraSpec parse_camera(const JsonObject& o) {
  CameraSpec c;
  if (o.has("auto")) {
    o.allow_only({"auto"});
    if (!o.boolean("auto")) o.fail("auto", "may only be true; give \"gltf_camera\", \"position\" or \"keys\" instead");
    c.auto_frame = true;
  } else if (o.has("gltf_camera")) {
    o.allow_only({"gltf_camera"});
    c.gltf_camera = o.integer("gltf_camera", 0, 1 << 20);
  } else if (o.has("keys")) {
    o.allow_only({"keys", "znear"});
    for (const JsonObject& k : o.objects("keys")) {
      k.allow_only({"frame", "position", "target", "vfov_deg", "cut"});
      c.keys.push_back(parse_camera_key(k, true));
      if (c.keys.size() > 1 && c.keys.back().frame <= c.keys[c.keys.size() - 2].frame) {
        k.fail("frame", "must be greater than the previous key's frame (keys are in increasing frame order)");
      }
    }
  } else if (o.has("position")) {
    o.allow_only({"position", "target", "vfov_deg", "znear"});
    c.keys.push_back(parse_camera_key(o, false));
  } else {
    throw InputError(o.file(), "'camera' needs one of: \"auto\": true, \"gltf_camera\", \"position\"+\"target\", or \"keys\"");
  }
  if (o.has("znear")) c.znear = static_cast<float>(o.number("znear", kZnear));
  return c;
}

glm::vec3 parse_color(const JsonObject& o, const char* key) {
  return glm::vec3(o.vec3(key, kNonNegative));
}

SunSpec parse_sun(const JsonObject& o) {
  SunSpec s;
  if (o.has("from_gltf")) {
    o.allow_only({"from_gltf", "illuminance", "color"});
    if (!o.boolean("from_gltf")) {
      o.fail("from_gltf", "may only be true; give \"azimuth_deg\"/\"elevation_deg\" or \"keys\" instead");
    }
    s.from_gltf = true;
  } else if (o.has("keys")) {
    o.allow_only({"keys", "illuminance", "color"});
    for (const JsonObject& k : o.objects("keys")) {
      k.allow_only({"frame", "azimuth_deg", "elevation_deg"});
      SunKey key;
      key.frame = k.integer("frame", 0, kMaxFrames);
      key.azimuth_deg = static_cast<float>(k.number("azimuth_deg", kAzimuth));
      key.elevation_deg = static_cast<float>(k.number("elevation_deg", kElevation));
      if (!s.keys.empty() && key.frame <= s.keys.back().frame) {
        k.fail("frame", "must be greater than the previous key's frame (keys are in increasing frame order)");
      }
      s.keys.push_back(key);
    }
  } else if (o.has("azimuth_deg") || o.has("elevation_deg")) {
    o.allow_only({"azimuth_deg", "elevation_deg", "illuminance", "color"});
    SunKey key;
    key.azimuth_deg = static_cast<float>(o.number("azimuth_deg", kAzimuth));
    key.elevation_deg = static_cast<float>(o.number("elevation_deg", kElevation));
    s.keys.push_back(key);
  } else {
    throw InputError(o.file(), "'sun' needs one of: \"from_gltf\": true, \"azimuth_deg\"+\"elevation_deg\", or \"keys\"");
  }
  if (o.has("illuminance")) s.illuminance = static_cast<float>(o.number("illuminance", {0.0, 1e9}));
  if (o.has("color")) s.color = parse_color(o, "color");
  return s;
}

AnimationSpec parse_animation(const JsonObject& o) {
  o.allow_only({"index", "name", "time", "fps"});
  AnimationSpec a;
  if (o.has("index") == o.has("name")) {
    throw InputError(o.file(), "'animation' needs exactly one of: \"index\" (a number) or \"name\" (a string)");
  }
  if (o.has("index")) a.index = o.integer("index", 0, 1 << 20);
  if (o.has("name")) a.name = o.string("name");
  if (o.has("time")) a.time_s = o.number("time", kNonNegative);
  if (o.has("fps")) a.fps = o.number("fps", {0.0, 1e6, true});
  return a;
}

// A file that cannot even be looked up (a name too long, a component not a
// folder, no permission) counts as absent: the caller names what it looked for.
bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

}  // namespace

float emissive_luminance(const SceneDescription& d) {
  return d.emissive_nits ? *d.emissive_nits : 1.2f * std::exp2(d.exposure_ev100);
}

SceneDescription load_scene_description(const std::string& path,
                                        const std::vector<std::string>& plugin_sections,
                                        const std::vector<std::string>& asset_dirs) {
  SceneDescription d;
  d.path = path;
  if (has_gltf_extension(path)) {
    if (!is_file(path)) throw InputError(path, "glTF file not found");
    d.gltf_path = path;
    d.sun.from_gltf = true;
    // A bare model gets a daylight fill so its shadowed side is readable at
    // the default exposure (EV100 15: 39000 cd/m^2 is white): an overcast-sky
    // radiance, slightly blue.
    d.ambient = glm::vec3(7000.0f, 7500.0f, 8500.0f);
    return d;
  }

  nlohmann::json doc = load_json_file(path);
  JsonObject root(doc, path, "");
  d.sun.from_gltf = true;  // a scene without a "sun" section lights like a bare glTF
  for (const std::string& key : root.keys()) {
    if (key == "gltf") {
      std::string rel = root.string("gltf");
      if (rel.empty()) root.fail(key, "must not be empty");
      fs::path p(rel);
      d.gltf_path = p.is_absolute() ? p.string() : (fs::path(path).parent_path() / p).string();
      if (!has_gltf_extension(d.gltf_path)) root.fail(key, "must name a .gltf or .glb file, found \"" + rel + "\"");
      std::string looked_in = d.gltf_path;
      for (size_t i = 0; !p.is_absolute() && !is_file(d.gltf_path) && i < asset_dirs.size(); ++i) {
        const std::string candidate = (fs::path(asset_dirs[i]) / p).string();
        looked_in += ", " + candidate;
        if (is_file(candidate)) d.gltf_path = candidate;
      }
      if (!is_file(d.gltf_path)) root.fail(key, "names a file that does not exist (looked for " + looked_in + ")");
    } else if (key == "camera") {
      d.camera = parse_camera(root.object("camera"));
    } else if (key == "sun") {
      d.sun = parse_sun(root.object("sun"));
    } else if (key == "exposure_ev100") {
      d.exposure_ev100 = static_cast<float>(root.number("exposure_ev100", {-30.0, 40.0}));
    } else if (key == "ambient") {
      d.ambient = parse_color(root, "ambient");
    } else if (key == "frames") {
      d.frames = root.integer("frames", 1, kMaxFrames);
    } else if (key == "emissive_nits") {
      d.emissive_nits = static_cast<float>(root.number("emissive_nits", {0.0, 1e9}));
    } else if (key == "animation") {
      d.animation = parse_animation(root.object("animation"));
    } else if (std::find(plugin_sections.begin(), plugin_sections.end(), key) != plugin_sections.end()) {
      d.plugins[key] = doc.at(key);  // validated by the plugin that owns the section
    } else {
      std::string allowed = "gltf, camera, sun, exposure_ev100, ambient, frames, emissive_nits, animation";
      for (const std::string& s : plugin_sections) allowed += ", " + s;
      throw InputError(path, "unknown key '" + key + "' (allowed: " + allowed + ")");
    }
  }
  if (d.gltf_path.empty()) throw InputError(path, "'gltf' is required (path of the glTF file, relative to the scene file)");
  return d;
}

}  // namespace cr

#pragma once
// A scene file (scenes/*.json): which glTF to load and how to view and light it.
// Documented in README.md ("Scene files"). A bare .gltf/.glb path is also a
// valid scene: camera from the glTF (or framing its bounds), sun from
// KHR_lights_punctual (or a default), no plugin sections.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "engine/core/colorimetry.h"

namespace cr {

// Camera pose at a frame; poses between keys are interpolated (position
// linearly, orientation by interpolating the look-at target). One key = static.
struct CameraKey {
  int frame = 0;
  glm::dvec3 position{0.0, 2.0, 10.0};
  glm::dvec3 target{0.0, 0.0, 0.0};
  float vfov_deg = 60.0f;
  bool cut = false;  // a camera cut happens at this key (no temporal history)
};

struct CameraSpec {
  // A three-quarter view fitting the scene's bounds (what a bare glTF without
  // a camera gets, and "camera": {"auto": true} / --camera auto).
  bool auto_frame = false;
  std::optional<int> gltf_camera;  // use the glTF camera with this index
  std::vector<CameraKey> keys;     // explicit keys (used when no gltf_camera)
  float znear = 0.1f;              // reversed-Z infinite projection: no far plane
};

// Sun direction per frame, interpolated between keys.
struct SunKey {
  int frame = 0;
  float azimuth_deg = 0.0f;    // clockwise from +Z (north) towards +X (east)
  float elevation_deg = 45.0f; // above the horizon; negative = below (night)
};

struct SunSpec {
  std::vector<SunKey> keys;          // empty: glTF sun or the default
  // The solar spectrum's at the top of the atmosphere (engine/core/colorimetry.h).
  glm::vec3 color = glm::vec3(solar_color());
  float illuminance = float(solar_illuminance_lux());  // lux at the top of the atmosphere / unattenuated
  bool from_gltf = false;
};

// "animation": {"index": N} or {"name": "Walk"}, optionally with "time":
// seconds (default 0): the glTF animation whose pose at that time is shown
// (times before its first or after its last keyframe hold that key), and
// "fps": frames per second of playback: frame f shows time + f / fps (a
// camera path runs the animation). No "animation" key: the rest pose.
struct AnimationSpec {
  std::optional<int> index;  // the glTF animation with this index, else
  std::string name;          // the first animation with this name
  double time_s = 0.0;
  std::optional<double> fps;  // nullopt: every frame shows time_s
  double time_at(int frame) const { return fps ? time_s + double(frame) / *fps : time_s; }
};

struct SceneDescription {
  std::string path;       // the scene file (or the glTF path for a bare glTF)
  std::string gltf_path;  // resolved relative to the scene file
  CameraSpec camera;
  SunSpec sun;
  float exposure_ev100 = 15.0f;  // photographic exposure; pixel = L / (1.2 * 2^EV100)
  glm::vec3 ambient{0.0f};      // fallback ambient radiance (cd/m^2) when no plugin supplies sky light
  int frames = 1;               // default frame count of the scene (CLI overrides)
  // Luminance (cd/m^2) of glTF emissive colour 1.0 (emissive factor times
  // texture times KHR_materials_emissive_strength) and of an unlit (KHR_materials_unlit)
  // base colour of 1.0. nullopt: the luminance the exposure maps to 1.0,
  // 1.2 * 2^EV100 (emissive_luminance), so glTF emissive reads as intended.
  std::optional<float> emissive_nits;
  std::optional<AnimationSpec> animation;  // nullopt: the rest pose (scene_animation.h poses it)
  nlohmann::json plugins = nlohmann::json::object();  // "atmosphere", "fog", ... sections
};

// Luminance of emissive 1.0 for the scene: emissive_nits, or 1.2 * 2^EV100.
float emissive_luminance(const SceneDescription& d);

// Loads a scene file or a bare .gltf/.glb. Throws InputError naming file and field.
// A relative "gltf" path is looked up next to the scene file, then in each of
// `asset_dirs` (the CLI passes the build's scenes/, where the generated
// default.glb lives, so shipped scene files also work from the source tree).
SceneDescription load_scene_description(const std::string& path,
                                        const std::vector<std::string>& plugin_sections,
                                        const std::vector<std::string>& asset_dirs = {});

}  // namespace cr

#pragma once
// Command-line overrides of a scene's view and light (--camera, --sun, --sky,
// --exposure): what a user needs to look at a bare glTF as in a viewer, and
// to try another view or light on a scene file without editing it.
#include <optional>
#include <string>

#include "engine/cli/arg_parser.h"
#include "engine/scene/scene_description.h"

namespace cr {

struct SceneOverrides {
  // --camera auto | N: the three-quarter view fitting the bounds, or the glTF's camera N.
  std::optional<std::string> camera;
  // --sun ELEVATION,AZIMUTH in degrees: one fixed sun (replaces the scene's).
  std::optional<std::pair<float, float>> sun;
  // --sky PRESET: the atmosphere plugin's section with this preset (replaces
  // the preset of a scene's own section, keeping its other keys).
  std::optional<std::string> sky;
  std::optional<float> exposure_ev100;  // --exposure EV100
};

// Declares the four options.
void add_scene_override_options(ArgParser& p);
// Reads them; UsageError naming `command` for malformed values.
SceneOverrides parse_scene_overrides(const ArgParser& p, const std::string& command);
// Applies them to a loaded description.
void apply_scene_overrides(const SceneOverrides& o, SceneDescription& d);

}  // namespace cr

#pragma once
// What the `auto` planner (engine/planning/auto_plan.h) asks of each module
// of a frame (the engine's own passes and each plugin): the options it may
// run at, measured for cost and error (profiles/auto_table.json), and the
// settings the scene itself decides.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/profile.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"

namespace cr {

// What the planner knows of a scene before rendering it: its camera and sun
// along the frames to render, and where its geometry lies from the camera.
struct SceneFacts {
  int frames = 1;
  int width = 0, height = 0;               // output resolution
  double max_camera_speed_m = 0.0;         // largest camera move between consecutive frames
  double max_camera_turn_deg = 0.0;        // largest turn of the view direction between frames
  double max_sun_turn_deg = 0.0;           // largest move of the sun between frames
  double min_sun_elevation_deg = 90.0;     // over the frames
  double max_sun_elevation_deg = -90.0;
  double min_camera_height_m = 0.0;        // camera y (the scene's up axis) over the frames
  double max_camera_height_m = 0.0;
  double max_geometry_distance_m = 0.0;    // farthest corner of the scene's bounds from any camera
  // The largest share of the view the scene's bounds cover on screen (their
  // projected rectangle; 1 where the camera is among them): an upper bound
  // of the pixels that shade geometry.
  double max_geometry_coverage = 0.0;
  bool has_geometry = false;
  bool camera_static() const { return max_camera_speed_m == 0.0 && max_camera_turn_deg == 0.0; }
  bool sun_static() const { return max_sun_turn_deg == 0.0; }
  bool moving() const { return !camera_static() || !sun_static(); }
  // The sun within 6 degrees of the horizon (or below) at some frame: long
  // grazing paths, where the sky's methods err most.
  bool twilight() const { return min_sun_elevation_deg < 6.0; }
  nlohmann::json to_json() const;
};

// One way a module may run: profile keys (dotted paths) and their values,
// with what they cost and how far from the ground truth they put the frame.
struct PlanOption {
  std::string name;
  nlohmann::json settings = nlohmann::json::object();  // {"fog.froxel_size_px": 16, ...}
  double cost_ms = 0.0;   // per frame at the table's resolution and threads (amortised over the frames)
  double error = 0.0;     // mean relative luminance error of the whole frame it adds
  // Its cost where the camera and the sun hold still (work that only
  // changing inputs trigger is then done once); unknown: cost_ms.
  std::optional<double> static_cost_ms;
  // Its error measured per table scene, with the scene's kind: the planner
  // takes the largest over the scenes of the planned scene's kind (moving or
  // still, twilight or day), else `error`, the largest over all.
  struct SceneError {
    std::string scene;
    bool moving = false;
    bool twilight = false;
    double error = 0.0;
  };
  std::vector<SceneError> errors;
};

// A setting the scene decides, whatever option is chosen, and why.
struct PlanChoice {
  std::string key;
  nlohmann::json value;
  std::string reason;
};

struct ModulePlan {
  std::string module;                // "engine", or the plugin's name
  bool used = true;                  // false: the scene does not use the module: no passes, no cost
  std::string note;                  // why it is unused, or what the scene changes about its options
  std::vector<PlanOption> options;   // at least one where used
  std::vector<PlanChoice> settings;  // applied on top of the chosen option
};

// What a module plans from: the scene, the base profile the plan starts from
// and the module's part of the table (an array of options).
struct PlanContext {
  const Scene& scene;
  const SceneDescription& description;
  const Profile& base;
  const SceneFacts& facts;
  const nlohmann::json& table_options;  // the module's "options" in the table
  const std::string& table_path;        // for messages
};

// The table's options as they are (each {"name", "settings", "cost_ms",
// "error"}); InputError naming `file` and the field when malformed.
std::vector<PlanOption> parse_plan_options(const nlohmann::json& options, const std::string& file,
                                           const std::string& module);

}  // namespace cr

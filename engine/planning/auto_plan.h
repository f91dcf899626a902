#pragma once
// `--profile auto`: a profile planned for one scene. Each module of the frame
// (the engine's passes and each plugin) offers options measured for cost and
// error (profiles/auto_table.json, written by tests/bench/auto_table.py);
// the planner picks one per module so that the errors' sum stays within the
// error budget at the least predicted cost, skips what the scene does not
// use and applies what the scene decides (module_plan.h). The plan is a pure
// function of the scene, the base profile, the table and the budget: the
// same inputs give the same profile on any machine.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/render/module_plan.h"
#include "engine/render/plugin.h"

namespace cr {

struct PlanTable {
  std::string path;
  nlohmann::json doc;
  int width = 0, height = 0;  // the resolution the costs were measured at
  // Per module: whether its cost grows with the pixel count (the engine's
  // passes, froxel grids) or not (LUTs).
  bool scales_with_pixels(const std::string& module) const;
  const nlohmann::json& options(const std::string& module) const;  // empty array when absent
};

// Reads and validates the table (InputError naming the file and field).
PlanTable load_plan_table(const std::string& path);

struct AutoPlan {
  double error_budget = 0.02;
  double frame_budget_ms = 33.3;
  std::string base;     // the base profile's path
  std::string table;    // the table's path
  SceneFacts facts;
  std::vector<ModulePlan> modules;
  std::vector<int> chosen;           // per module: the option index, -1 where unused
  std::vector<double> option_cost;   // per module: the chosen option's predicted cost at this resolution
  std::vector<double> option_error;  // and its predicted error for this scene
  double predicted_ms = 0.0;         // the chosen options' costs summed
  double predicted_error = 0.0;      // their errors summed (an upper bound of the frame's)
  bool meets_error_budget = false;   // false: no combination does; the most accurate one is chosen
  bool meets_frame_budget = false;   // predicted_ms <= frame_budget_ms
  nlohmann::json profile;            // the planned profile document

  nlohmann::json to_json() const;    // what report.json's "plan" holds
  std::string summary() const;       // the choices and reasons, printed by the commands
};

// Plans a profile for `scene` from `base_doc` (the base profile's document;
// `base` the same, parsed). `plugins` are the registry's (null entries: a
// section name only). Width and height are the output resolution, frames
// the frames that will be rendered.
AutoPlan plan_auto_profile(const Scene& scene, const SceneDescription& description, const nlohmann::json& base_doc,
                           const Profile& base, const PlanTable& table,
                           const std::vector<std::unique_ptr<Plugin>>& plugins, double error_budget, int frames,
                           int width, int height);

// The engine module's plan: the table's engine options, and no shadow pass
// where nothing casts a shadow.
ModulePlan plan_engine_module(const PlanContext& ctx);

}  // namespace cr

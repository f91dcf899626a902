#include "engine/planning/auto_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/profile_keys.h"
#include "engine/output/atomic_file.h"
#include "engine/planning/scene_facts.h"

namespace cr {

namespace {

const nlohmann::json& empty_array() {
  static const nlohmann::json a = nlohmann::json::array();
  return a;
}

std::string percent(double e) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f%%", 100.0 * e);
  return buf;
}

std::string ms(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f ms", v);
  return buf;
}

// The option's predicted cost for this scene: its still-scene cost where the
// camera and sun hold still, scaled to the output's pixel count where the
// module's work grows with it.
double predicted_cost(const PlanOption& o, const PlanTable& table, const std::string& module, const SceneFacts& f) {
  double c = f.camera_static() && f.sun_static() && o.static_cost_ms ? *o.static_cost_ms : o.cost_ms;
  if (table.scales_with_pixels(module))
    c *= double(f.width) * double(f.height) / (double(table.width) * double(table.height));
  return c;
}

// Its error for this scene: the largest measured on table scenes of its kind
// (moving or still, twilight or day), else the largest over all.
double predicted_error(const PlanOption& o, const SceneFacts& f) {
  double e = -1.0;
  for (const PlanOption::SceneError& m : o.errors)
    if (m.moving == f.moving() && m.twilight == f.twilight()) e = std::max(e, m.error);
  return e >= 0.0 ? e : o.error;
}

}  // namespace

bool PlanTable::scales_with_pixels(const std::string& module) const {
  return doc["modules"].contains(module) && doc["modules"][module].value("scales_with_pixels", false);
}

const nlohmann::json& PlanTable::options(const std::string& module) const {
  return doc["modules"].contains(module) ? doc["modules"][module]["options"] : empty_array();
}

PlanTable load_plan_table(const std::string& path) {
  PlanTable t;
  t.path = path;
  t.doc = nlohmann::json::parse(read_file_bytes(path), nullptr, false);
  if (t.doc.is_discarded() || !t.doc.is_object()) throw InputError(path, "not a JSON object");
  if (t.doc.value("format", "") != "cpurender-auto-table")
    throw InputError(path, "format: expected \"cpurender-auto-table\"");
  const nlohmann::json& m = t.doc["measured"];
  if (!m.is_object() || !m.contains("resolution") || !m["resolution"].is_array() || m["resolution"].size() != 2 ||
      !m["resolution"][0].is_number_integer() || !m["resolution"][1].is_number_integer() ||
      m["resolution"][0].get<int>() < 1 || m["resolution"][1].get<int>() < 1)
    throw InputError(path, "measured.resolution: expected [width, height]");
  t.width = m["resolution"][0].get<int>();
  t.height = m["resolution"][1].get<int>();
  if (!t.doc.contains("modules") || !t.doc["modules"].is_object() || !t.doc["modules"].contains("engine"))
    throw InputError(path, "modules: expected an object with at least \"engine\"");
  for (const auto& [name, module] : t.doc["modules"].items()) {
    if (!module.is_object()) throw InputError(path, "modules." + name + ": expected an object");
    for (const auto& [key, value] : module.items())
      if (key != "options" && key != "scales_with_pixels")
        throw InputError(path, "modules." + name + ": unknown key '" + key + "'");
    if (module.contains("scales_with_pixels") && !module["scales_with_pixels"].is_boolean())
      throw InputError(path, "modules." + name + ".scales_with_pixels: expected true or false");
    parse_plan_options(module.value("options", nlohmann::json()), path, name);
  }
  return t;
}

ModulePlan plan_engine_module(const PlanContext& ctx) {
  ModulePlan m;
  m.module = "engine";
  m.options = parse_plan_options(ctx.table_options, ctx.table_path, "engine");
  // A render scale saves shading where geometry covers the view but costs an
  // upscale of every output pixel (about 4 ms at 1280x720 on two cores,
  // against about 50 ms of engine passes over a fully covered view: scale
  // 0.75 saves 44% of those, which pays from about 20% coverage). The
  // table's engine costs come from covered views, so below that the planner
  // would buy a scale that costs more than it saves.
  constexpr double kScaleCoverage = 0.2;
  const auto scaled = [](const PlanOption& o) { return o.settings.value("render_scale", 1.0) != 1.0; };
  if (ctx.facts.max_geometry_coverage < kScaleCoverage && !std::all_of(m.options.begin(), m.options.end(), scaled)) {
    std::erase_if(m.options, scaled);
    char why[160];
    std::snprintf(why, sizeof why,
                  "geometry covers at most %.1f%% of the view: a lower render scale would save little shading "
                  "and add an upscale of every pixel",
                  100.0 * ctx.facts.max_geometry_coverage);
    m.settings.push_back({"render_scale", 1.0, why});
  }
  if (!ctx.facts.has_geometry) {
    m.settings.push_back({"shadow_map_size", 0, "no geometry: nothing casts or receives a shadow"});
  } else if (ctx.base.shadow_map_size > 0 && ctx.facts.max_geometry_distance_m < ctx.base.shadow_distance) {
    // The map's texels spread over the distance it covers: no farther than the geometry.
    const double d = std::ceil(ctx.facts.max_geometry_distance_m);
    m.settings.push_back({"shadow_distance", d,
                          "all geometry lies within " + std::to_string(int(d)) +
                              " m of the camera: the shadow map covers no farther"});
  }
  return m;
}

AutoPlan plan_auto_profile(const Scene& scene, const SceneDescription& description, const nlohmann::json& base_doc,
                           const Profile& base, const PlanTable& table,
                           const std::vector<std::unique_ptr<Plugin>>& plugins, double error_budget, int frames,
                           int width, int height) {
  if (!(error_budget > 0.0) || !std::isfinite(error_budget))
    throw InputError("--error-budget", "expected a number > 0 (a fraction: 0.02 is 2%)");
  AutoPlan plan;
  plan.error_budget = error_budget;
  plan.frame_budget_ms = base.frame_budget_ms;
  plan.base = base.path;
  plan.table = table.path;
  plan.facts = analyse_scene(scene, description, frames, width, height);
  plan.modules.push_back(plan_engine_module({scene, description, base, plan.facts, table.options("engine"), table.path}));
  for (const std::unique_ptr<Plugin>& p : plugins)
    if (p) plan.modules.push_back(p->plan({scene, description, base, plan.facts, table.options(p->name()), table.path}));

  // Every combination of one option per used module (the table keeps each
  // module's options few): the cheapest whose errors sum within the budget,
  // else the most accurate.
  const size_t n = plan.modules.size();
  std::vector<std::vector<double>> cost(n), error(n);
  size_t combinations = 1;
  for (size_t i = 0; i < n; ++i) {
    const ModulePlan& m = plan.modules[i];
    if (!m.used) continue;
    if (m.options.empty()) throw InputError(table.path, "modules." + m.module + ": no options for a module the scene uses");
    for (const PlanOption& o : m.options) {
      cost[i].push_back(predicted_cost(o, table, m.module, plan.facts));
      error[i].push_back(predicted_error(o, plan.facts));
    }
    combinations *= m.options.size();
    if (combinations > 1000000) throw InputError(table.path, "modules: more than a million option combinations");
  }
  std::vector<int> index(n, 0), best_fit, best_error;
  double fit_cost = std::numeric_limits<double>::infinity(), fit_error = 0.0;
  double min_error = std::numeric_limits<double>::infinity(), min_error_cost = 0.0;
  for (size_t c = 0; c < combinations; ++c) {
    size_t rest = c;
    double total_cost = 0.0, total_error = 0.0;
    for (size_t i = 0; i < n; ++i) {
      if (!plan.modules[i].used) {
        index[i] = -1;
        continue;
      }
      const size_t k = plan.modules[i].options.size();
      index[i] = int(rest % k);
      rest /= k;
      total_cost += cost[i][size_t(index[i])];
      total_error += error[i][size_t(index[i])];
    }
    // Strict comparisons: ties keep the first combination, so the plan is deterministic.
    if (total_error <= error_budget && (total_cost < fit_cost || (total_cost == fit_cost && total_error < fit_error))) {
      fit_cost = total_cost;
      fit_error = total_error;
      best_fit = index;
    }
    if (total_error < min_error || (total_error == min_error && total_cost < min_error_cost)) {
      min_error = total_error;
      min_error_cost = total_cost;
      best_error = index;
    }
  }
  plan.meets_error_budget = !best_fit.empty();
  plan.chosen = plan.meets_error_budget ? best_fit : best_error;
  plan.predicted_ms = plan.meets_error_budget ? fit_cost : min_error_cost;
  plan.predicted_error = plan.meets_error_budget ? fit_error : min_error;
  plan.meets_frame_budget = plan.predicted_ms <= plan.frame_budget_ms;

  plan.profile = base_doc;
  plan.profile["name"] = "auto";
  plan.option_cost.assign(n, 0.0);
  plan.option_error.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const ModulePlan& m = plan.modules[i];
    if (!m.used) continue;
    const PlanOption& o = m.options[size_t(plan.chosen[i])];
    plan.option_cost[i] = cost[i][size_t(plan.chosen[i])];
    plan.option_error[i] = error[i][size_t(plan.chosen[i])];
    for (const auto& [key, value] : o.settings.items()) set_profile_key(plan.profile, key, value);
    for (const PlanChoice& s : m.settings) set_profile_key(plan.profile, s.key, s.value);
  }
  return plan;
}

nlohmann::json AutoPlan::to_json() const {
  nlohmann::json j = {{"error_budget", error_budget},
                      {"frame_budget_ms", frame_budget_ms},
                      {"base", base},
                      {"table", table},
                      {"facts", facts.to_json()},
                      {"modules", nlohmann::json::array()},
                      {"choices", nlohmann::json::array()},
                      {"predicted_ms", predicted_ms},
                      {"predicted_error", predicted_error},
                      {"meets_error_budget", meets_error_budget},
                      {"meets_frame_budget", meets_frame_budget}};
  for (size_t i = 0; i < modules.size(); ++i) {
    const ModulePlan& m = modules[i];
    nlohmann::json mj = {{"module", m.module}, {"used", m.used}, {"note", m.note}};
    if (m.used) {
      const PlanOption& o = m.options[size_t(chosen[i])];
      mj["option"] = {{"name", o.name}, {"settings", o.settings}, {"predicted_ms", option_cost[i]}, {"predicted_error", option_error[i]}};
      mj["options_considered"] = m.options.size();
      const std::string why = meets_error_budget ? "the cheapest option whose error, with the other modules', fits " +
                                                       percent(error_budget)
                                                 : "no combination fits " + percent(error_budget) +
                                                       ": the most accurate";
      for (const auto& [key, value] : o.settings.items())
        j["choices"].push_back({{"key", key}, {"value", value}, {"reason", m.module + " option \"" + o.name + "\": " + why}});
    } else {
      j["choices"].push_back({{"key", m.module}, {"value", "off"}, {"reason", m.note}});
    }
    mj["settings"] = nlohmann::json::array();
    for (const PlanChoice& s : m.settings) {
      mj["settings"].push_back({{"key", s.key}, {"value", s.value}, {"reason", s.reason}});
      if (m.used) j["choices"].push_back({{"key", s.key}, {"value", s.value}, {"reason", s.reason}});
    }
    j["modules"].push_back(mj);
  }
  return j;
}

std::string AutoPlan::summary() const {
  std::string s = "auto profile (error budget " + percent(error_budget) + ", frame budget " + ms(frame_budget_ms) +
                  ", from " + base + " and " + table + "):\n";
  for (size_t i = 0; i < modules.size(); ++i) {
    const ModulePlan& m = modules[i];
    if (!m.used) {
      s += "  " + m.module + ": off (" + m.note + ")\n";
      continue;
    }
    const PlanOption& o = m.options[size_t(chosen[i])];
    s += "  " + m.module + ": \"" + o.name + "\" (" + ms(option_cost[i]) + ", error " + percent(option_error[i]) + ", of " +
         std::to_string(m.options.size()) + " options)" + (m.note.empty() ? "" : "; " + m.note) + "\n";
    for (const PlanChoice& c : m.settings)
      s += "    " + c.key + " = " + c.value.dump() + ": " + c.reason + "\n";
  }
  s += "  predicted " + ms(predicted_ms) + " per frame, error <= " + percent(predicted_error) + ": ";
  if (meets_error_budget && meets_frame_budget) s += "meets both budgets\n";
  else if (!meets_error_budget)
    s += "no setting in the table meets the error budget; this is the most accurate (the closest point)\n";
  else
    s += "over the frame budget at this error budget; this is the cheapest point that meets the error budget "
         "(the closest one)\n";
  return s;
}

}  // namespace cr

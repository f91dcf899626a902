#include "engine/render/module_plan.h"

#include <cmath>

#include "engine/core/error.h"

namespace cr {

nlohmann::json SceneFacts::to_json() const {
  return {{"frames", frames},
          {"resolution", {width, height}},
          {"camera_static", camera_static()},
          {"max_camera_speed_m_per_frame", max_camera_speed_m},
          {"max_camera_turn_deg_per_frame", max_camera_turn_deg},
          {"sun_static", sun_static()},
          {"max_sun_turn_deg_per_frame", max_sun_turn_deg},
          {"sun_elevation_deg", {min_sun_elevation_deg, max_sun_elevation_deg}},
          {"moving", moving()},
          {"twilight", twilight()},
          {"camera_height_m", {min_camera_height_m, max_camera_height_m}},
          {"has_geometry", has_geometry},
          {"max_geometry_distance_m", max_geometry_distance_m},
          {"max_geometry_coverage", max_geometry_coverage}};
}

std::vector<PlanOption> parse_plan_options(const nlohmann::json& options, const std::string& file,
                                           const std::string& module) {
  const std::string where = "modules." + module + ".options";
  if (!options.is_array() || options.empty()) throw InputError(file, where + ": expected a non-empty array");
  std::vector<PlanOption> out;
  for (size_t i = 0; i < options.size(); ++i) {
    const nlohmann::json& o = options[i];
    const std::string at = where + "[" + std::to_string(i) + "]";
    if (!o.is_object()) throw InputError(file, at + ": expected an object");
    for (const auto& [key, value] : o.items())
      if (key != "name" && key != "settings" && key != "cost_ms" && key != "error" && key != "static_cost_ms" &&
          key != "errors")
        throw InputError(file, at + ": unknown key '" + key + "'");
    PlanOption p;
    if (!o.contains("name") || !o["name"].is_string()) throw InputError(file, at + ".name: expected a string");
    p.name = o["name"].get<std::string>();
    if (!o.contains("settings") || !o["settings"].is_object())
      throw InputError(file, at + ".settings: expected an object of profile keys");
    p.settings = o["settings"];
    for (const char* k : {"cost_ms", "error"})
      if (!o.contains(k) || !o[k].is_number() || !(o[k].get<double>() >= 0.0) || !std::isfinite(o[k].get<double>()))
        throw InputError(file, at + "." + k + ": expected a finite number >= 0");
    p.cost_ms = o["cost_ms"].get<double>();
    p.error = o["error"].get<double>();
    if (o.contains("static_cost_ms")) {
      const nlohmann::json& c = o["static_cost_ms"];
      if (!c.is_number() || !(c.get<double>() >= 0.0) || !std::isfinite(c.get<double>()))
        throw InputError(file, at + ".static_cost_ms: expected a finite number >= 0");
      p.static_cost_ms = c.get<double>();
    }
    if (o.contains("errors")) {
      if (!o["errors"].is_array()) throw InputError(file, at + ".errors: expected an array");
      for (size_t k = 0; k < o["errors"].size(); ++k) {
        const nlohmann::json& e = o["errors"][k];
        const std::string ek = at + ".errors[" + std::to_string(k) + "]";
        if (!e.is_object() || !e.contains("scene") || !e["scene"].is_string() || !e.contains("moving") ||
            !e["moving"].is_boolean() || !e.contains("twilight") || !e["twilight"].is_boolean() ||
            !e.contains("error") || !e["error"].is_number() || !(e["error"].get<double>() >= 0.0) ||
            !std::isfinite(e["error"].get<double>()))
          throw InputError(file, ek + ": expected {\"scene\", \"moving\", \"twilight\", \"error\" >= 0}");
        p.errors.push_back({e["scene"].get<std::string>(), e["moving"].get<bool>(), e["twilight"].get<bool>(),
                            e["error"].get<double>()});
      }
    }
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace cr

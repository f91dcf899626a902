#include "engine/output/stability_map.h"

#include "engine/output/atomic_file.h"

namespace cr {

namespace {

nlohmann::json axis_json(const StabilityAxis& a) {
  return {{"name", a.name}, {"scale", a.scale}, {"values", a.values}};
}

}  // namespace

nlohmann::json to_json(const StabilityMap& map) {
  nlohmann::json grids = nlohmann::json::array();
  for (const StabilityGrid& g : map.grids) {
    nlohmann::json cells = nlohmann::json::array();
    for (const StabilityCell& c : g.cells) {
      nlohmann::json fallbacks = nlohmann::json::object();
      for (const auto& [name, share] : c.fallbacks) fallbacks[name] = share;
      cells.push_back({{"x", c.x},
                       {"y", c.y},
                       {"scored", c.scored},
                       {"error_mean", c.error_mean},
                       {"error_p95", c.error_p95},
                       {"noise_mean", c.noise_mean},
                       {"non_finite", c.non_finite},
                       {"fallbacks", fallbacks},
                       {"details", c.details}});
    }
    grids.push_back({{"name", g.name},
                     {"x", axis_json(g.x)},
                     {"y", axis_json(g.y)},
                     {"fallbacks", g.fallbacks},
                     {"fixed", g.fixed},
                     {"cells", cells}});
  }
  return {{"schema", kStabilitySchema},
          {"method", map.method},
          {"ground_truth", map.ground_truth},
          {"command", map.command},
          {"thresholds", map.thresholds},
          {"settings", map.settings},
          {"seconds", map.seconds},
          {"grids", grids}};
}

void write_stability_json(const std::string& path, const StabilityMap& map) {
  write_file_atomic(path, to_json(map).dump(1) + "\n");
}

}  // namespace cr

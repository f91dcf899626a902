#pragma once
// The stability map's data (docs/stability.md, "stability.json"): a method
// evaluated over 2-D grids of its inputs against a ground truth. Each cell
// carries the error, the ground truth's own noise, the count of non-finite
// values and how much each fallback engaged. The sky and the fog commands
// write the same schema, which tools/stability/stability_map.py draws.
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cr {

inline constexpr const char* kStabilitySchema = "cpurender-stability/1";

struct StabilityAxis {
  std::string name;   // with its unit: "sun_zenith_deg"
  std::string scale;  // how to draw it: "linear", "log", or "symlog" (log with a linear part around 0)
  std::vector<double> values;
};

struct StabilityCell {
  int x = 0, y = 0;  // indices into the grid's axes
  bool scored = false;  // false: no pixel could be scored (all dark), the errors mean nothing
  double error_mean = 0.0, error_p95 = 0.0;
  double noise_mean = 0.0;  // the ground truth's relative standard error (or convergence error), mean
  size_t non_finite = 0;    // NaN or Inf values over every buffer the cell produced
  // Per fallback named by the grid: the share of the cell where it engaged (0 = not at all, 1 = all of it).
  std::vector<std::pair<std::string, double>> fallbacks;
  nlohmann::json details = nlohmann::json::object();  // counters behind the figures (method-specific)
};

struct StabilityGrid {
  std::string name;
  StabilityAxis x, y;
  std::vector<std::string> fallbacks;  // the names the cells use
  nlohmann::json fixed = nlohmann::json::object();  // the inputs held constant over the grid
  std::vector<StabilityCell> cells;
};

struct StabilityMap {
  std::string method, ground_truth, command;
  std::vector<double> thresholds;  // mean relative errors the plot contours
  nlohmann::json settings = nlohmann::json::object();
  std::vector<StabilityGrid> grids;
  double seconds = 0.0;  // the whole run's wall time
};

nlohmann::json to_json(const StabilityMap& map);
// Writes to_json(map) to `path` atomically.
void write_stability_json(const std::string& path, const StabilityMap& map);

// Non-finite values among `values` (or among the components of RGB values).
inline size_t count_non_finite(std::span<const float> values) {
  size_t n = 0;
  for (float v : values) n += std::isfinite(v) ? 0 : 1;
  return n;
}
inline size_t count_non_finite(std::span<const glm::vec3> values) {
  return count_non_finite(std::span<const float>(reinterpret_cast<const float*>(values.data()), values.size() * 3));
}

}  // namespace cr

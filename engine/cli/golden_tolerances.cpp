#include "engine/cli/golden_tolerances.h"

#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace cr {

namespace {

constexpr const char* kMetrics[] = {"max_abs", "rmse", "pixel_threshold", "max_fraction", "flip_mean"};

CompareThresholds parse_entry(const JsonObject& entry) {
  entry.allow_only({"max_abs", "rmse", "pixel_threshold", "max_fraction", "flip_mean", "why"});
  // Display values lie in [0,1]; FLIP and fractions too. A threshold of 1
  // therefore disables a metric, which stays expressible.
  const NumberRange unit{0.0, 1.0};
  CompareThresholds t;
  t.max_abs = entry.number("max_abs", unit);
  t.rmse = entry.number("rmse", unit);
  t.pixel_threshold = entry.number("pixel_threshold", unit);
  t.max_fraction = entry.number("max_fraction", unit);
  t.flip_mean = entry.number("flip_mean", unit);
  const JsonObject why = entry.object("why");
  why.allow_only({"max_abs", "rmse", "pixel_threshold", "max_fraction", "flip_mean"});
  for (const char* metric : kMetrics)
    if (why.string(metric).empty()) why.fail(metric, "must explain the chosen value");
  return t;
}

}  // namespace

GoldenTolerances GoldenTolerances::load(const std::string& path) {
  const nlohmann::json doc = load_json_file(path);
  const JsonObject root(doc, path, "");
  root.allow_only({"comment", "profiles"});
  GoldenTolerances t;
  t.path_ = path;
  const JsonObject profiles = root.object("profiles");
  if (!profiles.has("default")) throw InputError(path, "profiles.default is required (used by profiles without an entry)");
  for (const std::string& name : profiles.keys()) t.entries_[name] = parse_entry(profiles.object(name.c_str()));
  return t;
}

GoldenTolerance GoldenTolerances::for_profile(const std::string& profile) const {
  const auto it = entries_.find(profile);
  if (it != entries_.end()) return {profile, it->second};
  return {"default", entries_.at("default")};
}

}  // namespace cr

#pragma once
// The modules' own ground truths, for `cpurender sweep`: each plugin's tools
// register a measure of their module's method against their reference (the
// path-traced sky, the ray-marched fog), so the sweep can record a module's
// error without the engine knowing any module. Filled by the composition
// root, like CommandRegistry.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/profile.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"

namespace cr {

// One sweep point, after its frames were rendered: the scene is posed as at
// the measured (last) frame.
struct ModuleTruthRequest {
  const Scene& scene;
  const SceneDescription& description;
  const Profile& profile;  // the point's (validated, planned for auto points)
  const nlohmann::json& profile_document;  // the same as JSON: what a cached reference is keyed by
  int width = 0, height = 0;
  int frame = 0;  // the measured frame
  unsigned threads = 1;
  // The module's settings, {KEY: integer}: its defaults with the sweep's --truth-setting values.
  nlohmann::json settings;
  // Where references are cached, and the build's hash (cache_key.h): a
  // reference is named by everything it depends on.
  std::string cache_dir;
  std::string build_hash;
};

struct ModuleTruthResult {
  double rel_luminance_mean = 0.0;
  double rel_luminance_p95 = 0.0;
  std::string reference;        // what it was measured against, in words (sizes, samples)
  std::optional<double> noise;  // the reference's own mean relative noise, where known
  bool reference_cached = false;  // read from cache_dir rather than rendered
};

// A reference's size or sample count: an integer in [min, max].
struct TruthSetting {
  std::string key;
  int value = 0;  // the default
  int min = 0, max = 0;
};

struct ModuleTruth {
  std::string module;  // "atmosphere", "fog": the prefix of the module's passes
  std::vector<TruthSetting> settings;
  // nullopt: the scene does not use the module (no truth to measure).
  std::function<std::optional<ModuleTruthResult>(const ModuleTruthRequest&)> measure;
};

class ModuleTruthRegistry {
 public:
  void add(ModuleTruth truth);  // throws Error on a module added twice
  const std::vector<ModuleTruth>& truths() const { return truths_; }
  const ModuleTruth* find(const std::string& module) const;  // nullptr when not registered

 private:
  std::vector<ModuleTruth> truths_;
};

}  // namespace cr

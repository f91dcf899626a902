#pragma once
// Which modules' ground truths a sweep measures (--truth, --truth-setting),
// and each point's "module_error" record of them.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/cli/module_truth.h"

namespace cr {

struct SweepTruths {
  std::vector<const ModuleTruth*> modules;  // in registration order
  nlohmann::json settings = nlohmann::json::object();  // module -> its settings
  // {"modules": [...], "settings": {...}}: part of what the sweep is, for --resume.
  nlohmann::json definition() const;
};

// `which`: {"all"} (every registered module), {"none"}, or module names;
// `settings`: "MODULE.KEY=VALUE" each, VALUE an integer in the setting's
// range. UsageError on an unknown, empty or repeated
// module, an unknown key, or a malformed value.
SweepTruths select_truths(const ModuleTruthRegistry& registry, const std::vector<std::string>& which,
                          const std::vector<std::string>& settings);

// The point's "module_error": per module that the scene uses, its mean and
// p95 relative luminance error against its own reference, the reference in
// words, its noise (null when unknown), and the measurement's time.
// `request.settings` is ignored: each module gets its own.
nlohmann::json measure_truths(const SweepTruths& truths, const ModuleTruthRequest& request);

// The CSV header cells and a row's cells: <module>_truth_mean,<module>_truth_p95 per selected module.
std::string truth_csv_header(const nlohmann::json& definition);
std::string truth_csv_cells(const nlohmann::json& definition, const nlohmann::json& row);

}  // namespace cr

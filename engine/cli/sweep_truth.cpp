#include "engine/cli/sweep_truth.h"

#include <chrono>
#include <cstdio>
#include <set>

#include "engine/cli/arg_parser.h"
#include "engine/core/error.h"

namespace cr {

namespace {

void set_truth_setting(SweepTruths& t, const std::string& text) {
  const size_t dot = text.find('.'), eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || dot > eq)
    throw UsageError("--truth-setting '" + text + "': expected MODULE.KEY=VALUE (e.g. atmosphere.paths=256)");
  const std::string module = text.substr(0, dot), key = text.substr(dot + 1, eq - dot - 1);
  const ModuleTruth* m = nullptr;
  for (const ModuleTruth* candidate : t.modules)
    if (candidate->module == module) m = candidate;
  if (!m) throw UsageError("--truth-setting '" + text + "': '" + module + "' is not a measured module (see --truth)");
  std::string known;
  for (const TruthSetting& s : m->settings) {
    known += known.empty() ? s.key : ", " + s.key;
    if (s.key != key) continue;
    const nlohmann::json value = nlohmann::json::parse(text.substr(eq + 1), nullptr, false);
    if (value.is_discarded() || !value.is_number_integer() || value.get<long long>() < s.min ||
        value.get<long long>() > s.max)
      throw UsageError("--truth-setting '" + text + "': expected an integer in [" + std::to_string(s.min) + ", " +
                       std::to_string(s.max) + "]");
    t.settings[module][key] = value;
    return;
  }
  throw UsageError("--truth-setting '" + text + "': " + module + " has no setting '" + key + "' (" + known + ")");
}

}  // namespace

nlohmann::json SweepTruths::definition() const {
  nlohmann::json names = nlohmann::json::array();
  for (const ModuleTruth* m : modules) names.push_back(m->module);
  return {{"modules", names}, {"settings", settings}};
}

SweepTruths select_truths(const ModuleTruthRegistry& registry, const std::vector<std::string>& which,
                          const std::vector<std::string>& settings) {
  std::string known = "all, none";
  for (const ModuleTruth& r : registry.truths()) known += ", " + r.module;
  SweepTruths t;
  if (which.size() == 1 && which[0] == "all") {
    for (const ModuleTruth& m : registry.truths()) t.modules.push_back(&m);
  } else if (which.size() != 1 || which[0] != "none") {
    if (which.empty()) throw UsageError("--truth: expected all, none or a list of modules (" + known + ")");
    std::set<std::string> seen;
    for (const std::string& name : which) {
      const ModuleTruth* m = registry.find(name);
      if (!m) throw UsageError("--truth: '" + name + "' is not a module with a ground truth (" + known + ")");
      if (!seen.insert(name).second) throw UsageError("--truth: '" + name + "' twice");
      t.modules.push_back(m);
    }
  }
  for (const ModuleTruth* m : t.modules) {
    t.settings[m->module] = nlohmann::json::object();
    for (const TruthSetting& s : m->settings) t.settings[m->module][s.key] = s.value;
  }
  for (const std::string& s : settings) set_truth_setting(t, s);
  return t;
}

nlohmann::json measure_truths(const SweepTruths& truths, const ModuleTruthRequest& request) {
  nlohmann::json out = nlohmann::json::object();
  for (const ModuleTruth* m : truths.modules) {
    const auto t0 = std::chrono::steady_clock::now();
    ModuleTruthRequest r = request;
    r.settings = truths.settings[m->module];
    const std::optional<ModuleTruthResult> result = m->measure(r);
    if (!result) continue;  // the scene does not use the module
    out[m->module] = {{"rel_luminance_mean", result->rel_luminance_mean},
                      {"rel_luminance_p95", result->rel_luminance_p95},
                      {"reference", result->reference},
                      {"noise", result->noise ? nlohmann::json(*result->noise) : nlohmann::json()},
                      {"reference_cached", result->reference_cached},
                      {"measure_ms", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()}};
  }
  return out;
}

std::string truth_csv_header(const nlohmann::json& definition) {
  std::string out;
  for (const nlohmann::json& m : definition["modules"]) {
    const std::string module = m.get<std::string>();
    out += ',';
    out += module + "_truth_mean," + module + "_truth_p95";
  }
  return out;
}

std::string truth_csv_cells(const nlohmann::json& definition, const nlohmann::json& row) {
  std::string out;
  const nlohmann::json errors = row.value("module_error", nlohmann::json::object());
  for (const nlohmann::json& m : definition["modules"]) {
    const nlohmann::json e = errors.value(m.get<std::string>(), nlohmann::json::object());
    for (const char* k : {"rel_luminance_mean", "rel_luminance_p95"}) {
      char buf[32] = "";
      if (e.contains(k) && e[k].is_number()) std::snprintf(buf, sizeof buf, "%.6f", e[k].get<double>());
      out += std::string(",") + buf;
    }
  }
  return out;
}

}  // namespace cr

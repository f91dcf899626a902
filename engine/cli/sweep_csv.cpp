#include "engine/cli/sweep_csv.h"

#include <cstdio>
#include <set>

#include "engine/cli/sweep_truth.h"

namespace cr {

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

std::string sweep_csv(const nlohmann::json& doc) {
  std::vector<std::string> keys;
  for (const nlohmann::json& a : doc["axes"]) keys.push_back(a["key"].get<std::string>());
  std::set<std::string> passes;
  for (const nlohmann::json& p : doc["points"])
    for (const auto& [name, v] : p["passes"].items()) passes.insert(name);
  std::string out = "point,";
  for (const std::string& k : keys) out += csv_field(k) + ",";
  out += "threads,frame_ms_p50,frame_ms_p95,frame_ms_p99,rel_luminance_mean,rel_luminance_p95,flip_mean";
  out += truth_csv_header(doc["truth"]);
  for (const std::string& name : passes)
    for (const char* stat : {" p50", " p95", " mean"}) {
      out += ',';
      out += csv_field(name + stat);
    }
  out += "\n";
  for (const nlohmann::json& p : doc["points"]) {
    out += csv_field(p["point"].get<std::string>()) + ",";
    for (const std::string& k : keys) {
      const nlohmann::json& v = p["settings"].value(k, nlohmann::json());
      out += (v.is_null() ? std::string() : csv_field(v.is_string() ? v.get<std::string>() : v.dump())) + ",";
    }
    char buf[160];
    std::snprintf(buf, sizeof buf, "%u,%.4f,%.4f,%.4f", p["threads"].get<unsigned>(), p["frame_ms_p50"].get<double>(),
                  p["frame_ms_p95"].get<double>(), p.value("frame_ms_p99", p["frame_ms_p95"]).get<double>());
    out += buf;
    for (const char* e : {"rel_luminance_mean", "rel_luminance_p95", "flip_mean"}) {
      const nlohmann::json& v = p["error"][e];
      if (v.is_number()) std::snprintf(buf, sizeof buf, ",%.6f", v.get<double>());
      out += v.is_number() ? std::string(buf) : std::string(",");
    }
    out += truth_csv_cells(doc["truth"], p);
    for (const std::string& name : passes) {
      if (!p["passes"].contains(name)) {
        out += ",,,";
        continue;
      }
      const nlohmann::json& pass = p["passes"][name];
      std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f", pass["p50"].get<double>(), pass["p95"].get<double>(),
                    pass.value("mean", pass["p50"]).get<double>());
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace cr

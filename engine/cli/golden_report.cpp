#include "engine/cli/golden_report.h"

#include <cstdio>
#include <map>
#include <stdexcept>

#include "engine/core/error.h"

namespace cr {

const char* to_string(GoldenStatus status) {
  switch (status) {
    case GoldenStatus::Pass: return "pass";
    case GoldenStatus::Fail: return "FAIL";
    case GoldenStatus::Error: return "ERROR";
    case GoldenStatus::Unchanged: return "unchanged";
    case GoldenStatus::Kept: return "kept";
    case GoldenStatus::Updated: return "UPDATED";
    case GoldenStatus::Added: return "ADDED";
  }
  return "?";
}

namespace {

// compare_result_to_json's encoding of metrics and thresholds (inf as "inf").
nlohmann::json compare_json(const GoldenRow& row) {
  CompareResult result;
  if (row.metrics) result.metrics = *row.metrics;
  return compare_result_to_json(result, row.thresholds);
}

std::string fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string thresholds_line(const CompareThresholds& t) {
  return "max_abs <= " + fmt("%.4g", t.max_abs) + ", rmse <= " + fmt("%.4g", t.rmse) + ", pixels over " +
         fmt("%.4g", t.pixel_threshold) + " <= " + fmt("%.4g", t.max_fraction * 100.0) +
         "%, FLIP mean <= " + fmt("%.4g", t.flip_mean);
}

}  // namespace

nlohmann::json golden_row_json(const GoldenRow& r) {
  const nlohmann::json compared = compare_json(r);
  nlohmann::json row = {
      {"case", r.case_name},
      {"scene", r.scene},
      {"profile", r.profile},
      {"frame", r.frame},
      {"golden", r.golden},
      {"status", to_string(r.status)},
      {"failures", r.failures},
      {"tolerance_entry", r.tolerance_entry},
      {"thresholds", compared["thresholds"]},
      {"metrics", r.metrics ? compared["metrics"] : nlohmann::json(nullptr)},
      {"deterministic", r.deterministic},
      {"render_ms", {{"threads_1", r.ms_one_thread}, {"threads_" + std::to_string(r.threads), r.ms_threads}}},
  };
  if (!r.determinism_detail.empty()) row["determinism_detail"] = r.determinism_detail;
  if (!r.diff_image.empty()) row["diff_image"] = r.diff_image;
  if (!r.flip_image.empty()) row["flip_image"] = r.flip_image;
  if (!r.new_image.empty()) row["new_image"] = r.new_image;
  return row;
}

GoldenRow golden_row_from_json(const nlohmann::json& j, const std::string& file) {
  GoldenRow r;
  try {
    r.case_name = j.at("case").get<std::string>();
    r.scene = j.at("scene").get<std::string>();
    r.profile = j.at("profile").get<std::string>();
    r.frame = j.at("frame").get<int>();
    r.golden = j.at("golden").get<std::string>();
    const std::string status = j.at("status").get<std::string>();
    bool known = false;
    for (GoldenStatus s : {GoldenStatus::Pass, GoldenStatus::Fail, GoldenStatus::Error, GoldenStatus::Unchanged,
                           GoldenStatus::Kept, GoldenStatus::Updated, GoldenStatus::Added})
      if (status == to_string(s)) {
        r.status = s;
        known = true;
      }
    if (!known) throw InputError(file, "golden row: unknown status \"" + status + "\"");
    r.failures = j.at("failures").get<std::vector<std::string>>();
    r.tolerance_entry = j.at("tolerance_entry").get<std::string>();
    r.thresholds = compare_thresholds_from_json(j.at("thresholds"));
    if (!j.at("metrics").is_null()) r.metrics = compare_metrics_from_json(j.at("metrics"));
    r.deterministic = j.at("deterministic").get<bool>();
    for (const auto& [key, ms] : j.at("render_ms").items()) {
      if (key == "threads_1") r.ms_one_thread = ms.get<double>();
      else if (key.rfind("threads_", 0) == 0) {
        r.threads = unsigned(std::stoul(key.substr(8)));
        r.ms_threads = ms.get<double>();
      }
    }
    r.determinism_detail = j.value("determinism_detail", "");
    r.diff_image = j.value("diff_image", "");
    r.flip_image = j.value("flip_image", "");
    r.new_image = j.value("new_image", "");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed golden row: ") + e.what());
  } catch (const std::logic_error& e) {  // stoul
    throw InputError(file, std::string("malformed golden row: ") + e.what());
  }
  return r;
}

GoldenReport golden_report_from_json(const nlohmann::json& j, const std::string& file) {
  GoldenReport report;
  try {
    report.mode = j.at("mode").get<std::string>();
    report.golden_dir = j.at("golden_dir").get<std::string>();
    report.tolerances = j.at("tolerances").get<std::string>();
    report.report_dir = j.at("report_dir").get<std::string>();
    report.width = j.at("resolution").at(0).get<int>();
    report.height = j.at("resolution").at(1).get<int>();
    report.threads = j.at("threads").at(1).get<unsigned>();
    for (const nlohmann::json& row : j.at("rows")) report.rows.push_back(golden_row_from_json(row, file));
    report.stale = j.at("stale_goldens").get<std::vector<std::string>>();
    report.pruned = j.at("pruned").get<bool>();
    report.wrote_goldens = j.at("wrote_goldens").get<bool>();
    report.note = j.at("note").get<std::string>();
    report.wall_s = j.at("wall_s").get<double>();
    report.exit_code = j.at("exit_code").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed golden report: ") + e.what());
  }
  return report;
}

nlohmann::json golden_report_json(const GoldenReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const GoldenRow& r : report.rows) rows.push_back(golden_row_json(r));
  std::map<std::string, int> counts;
  for (const GoldenRow& r : report.rows) ++counts[to_string(r.status)];
  return {
      {"mode", report.mode},
      {"golden_dir", report.golden_dir},
      {"tolerances", report.tolerances},
      {"report_dir", report.report_dir},
      {"resolution", {report.width, report.height}},
      {"threads", {1, report.threads}},
      {"rows", rows},
      {"counts", counts},
      {"stale_goldens", report.stale},
      {"pruned", report.pruned},
      {"wrote_goldens", report.wrote_goldens},
      {"note", report.note},
      {"wall_s", report.wall_s},
      {"exit_code", report.exit_code},
  };
}

std::string format_golden_report(const GoldenReport& report) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "golden %s: %zu image(s) at %dx%d, 1 vs %u threads, goldens in %s\n",
                report.mode.c_str(), report.rows.size(), report.width, report.height, report.threads,
                report.golden_dir.c_str());
  out += line;
  if (!report.note.empty()) out += "note: " + report.note + "\n";

  std::map<std::string, CompareThresholds> entries;
  for (const GoldenRow& r : report.rows) entries.emplace(r.tolerance_entry, r.thresholds);
  out += "tolerances (" + report.tolerances + "):\n";
  for (const auto& [name, t] : entries) out += "  " + name + ": " + thresholds_line(t) + "\n";

  std::snprintf(line, sizeof line, "\n%-34s %5s %-9s %8s %9s %7s %8s %8s %9s %9s %-5s %s\n", "case", "frame",
                "status", "max_abs", "rmse", "psnr", "over%", "flip", "ms 1T", "ms NT", "det", "tolerance");
  out += line;
  for (const GoldenRow& r : report.rows) {
    std::string max_abs = "-", rmse = "-", psnr = "-", over = "-", flip = "-";
    if (r.metrics) {
      max_abs = fmt("%.4f", r.metrics->max_abs);
      rmse = fmt("%.5f", r.metrics->rmse);
      psnr = format_psnr(r.metrics->psnr_db);
      if (psnr != "inf") psnr = fmt("%.1f", r.metrics->psnr_db);
      over = fmt("%.3f", r.metrics->fraction_over * 100.0);
      flip = fmt("%.5f", r.metrics->flip_mean);
    }
    std::snprintf(line, sizeof line, "%-34s %5d %-9s %8s %9s %7s %8s %8s %9.1f %9.1f %-5s %s\n",
                  r.case_name.c_str(), r.frame, to_string(r.status), max_abs.c_str(), rmse.c_str(), psnr.c_str(),
                  over.c_str(), flip.c_str(), r.ms_one_thread, r.ms_threads,
                  r.status == GoldenStatus::Error ? "-" : r.deterministic ? "ok" : "DIFF",
                  r.tolerance_entry.c_str());
    out += line;
  }

  bool header = false;
  for (const GoldenRow& r : report.rows) {
    if (r.failures.empty() && r.diff_image.empty() && r.new_image.empty()) continue;
    if (!header) out += "\ndetails:\n";
    header = true;
    std::snprintf(line, sizeof line, "  %s frame %d (%s):\n", r.case_name.c_str(), r.frame, to_string(r.status));
    out += line;
    for (const std::string& f : r.failures) out += "    " + f + "\n";
    if (!r.determinism_detail.empty()) out += "    determinism: " + r.determinism_detail + "\n";
    if (!r.diff_image.empty()) out += "    difference heat map: " + r.diff_image + "\n";
    if (!r.flip_image.empty()) out += "    FLIP heat map:       " + r.flip_image + "\n";
    if (!r.new_image.empty()) out += "    new render:          " + r.new_image + "\n";
  }

  if (!report.stale.empty()) {
    out += report.pruned ? "\nstale goldens deleted (--prune):\n"
                         : "\nstale goldens (no case renders them; `--update --prune` deletes them):\n";
    for (const std::string& s : report.stale) out += "  " + s + "\n";
  }

  std::map<std::string, int> counts;
  for (const GoldenRow& r : report.rows) ++counts[to_string(r.status)];
  out += "\nsummary:";
  for (const auto& [status, n] : counts) {
    std::snprintf(line, sizeof line, " %d %s,", n, status.c_str());
    out += line;
  }
  if (!report.note.empty()) out += " " + report.note + ",";
  std::snprintf(line, sizeof line, " %.1f s, exit %d\n", report.wall_s, report.exit_code);
  out += line;
  return out;
}

}  // namespace cr

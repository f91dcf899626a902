#pragma once
// The golden run's report: one row per golden image (case and kept frame)
// with its metrics, thresholds, verdict, render times and difference images,
// as JSON (golden_report.json) and as a readable table (golden_report.txt).
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/output/image_compare.h"

namespace cr {

enum class GoldenStatus {
  Pass,       // check: within the profile's tolerances (and deterministic)
  Fail,       // check: a threshold exceeded, golden missing/unreadable/resized, or 1 vs N threads differ
  Error,      // the case could not be rendered (its message is in `failures`)
  Unchanged,  // update: same pixels as the golden, not rewritten
  Kept,       // update: differs within tolerances, not rewritten (unless --exact)
  Updated,    // update: golden rewritten
  Added,      // update: golden created
};
const char* to_string(GoldenStatus status);

struct GoldenRow {
  std::string case_name;  // "<scene>.<profile>"
  std::string scene, profile;
  int frame = 0;
  std::string golden;     // golden file path
  GoldenStatus status = GoldenStatus::Pass;
  std::optional<CompareMetrics> metrics;  // absent when nothing could be compared
  std::string tolerance_entry;            // tolerances.json entry used
  CompareThresholds thresholds;
  std::vector<std::string> failures;      // why the row failed or errored
  unsigned threads = 0;
  double ms_one_thread = 0.0;  // the whole case's frames 0..last (shared by its rows)
  double ms_threads = 0.0;
  bool deterministic = true;
  std::string determinism_detail;
  std::string diff_image;  // report-dir heat maps and render, when written
  std::string flip_image;
  std::string new_image;
};

struct GoldenReport {
  std::string mode;  // "check" or "update"
  std::string golden_dir, tolerances, report_dir;
  int width = 0, height = 0;
  unsigned threads = 0;
  std::vector<GoldenRow> rows;
  std::vector<std::string> stale;   // goldens no case produces
  bool pruned = false;              // stale goldens were deleted
  bool wrote_goldens = false;       // update mode: goldens were written
  std::string note;                 // why update wrote nothing, etc.
  double wall_s = 0.0;
  int exit_code = 0;
};

nlohmann::json golden_report_json(const GoldenReport& report);
nlohmann::json golden_row_json(const GoldenRow& row);
// The inverses (what `golden --resume` and `merge` read back); InputError
// naming `file` when a field is missing or mistyped.
GoldenRow golden_row_from_json(const nlohmann::json& row, const std::string& file);
GoldenReport golden_report_from_json(const nlohmann::json& report, const std::string& file);
std::string format_golden_report(const GoldenReport& report);

}  // namespace cr

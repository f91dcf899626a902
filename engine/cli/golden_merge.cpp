// merge_golden: the shards' golden reports as one, rows in case order, their
// review images copied beside it, the exit status recomputed.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>

#include "engine/cli/golden_report.h"
#include "engine/cli/shard_merge.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"

namespace cr {

namespace fs = std::filesystem;

int merge_golden(const std::vector<ShardDir>& shards, const std::string& out) {
  fs::create_directories(out);
  std::map<std::string, std::vector<GoldenRow>> rows;  // by case
  GoldenReport merged;
  for (const ShardDir& s : shards) {
    const std::string file = s.dir + "/golden_report.json";
    if (!fs::exists(file)) throw InputError(file, "missing: the shard's check did not finish");
    const nlohmann::json j = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (j.is_discarded()) throw InputError(file, "not valid JSON");
    GoldenReport r = golden_report_from_json(j, file);
    for (GoldenRow& row : r.rows) {
      for (std::string* image : {&row.diff_image, &row.flip_image, &row.new_image})
        if (!image->empty() && fs::exists(*image)) {
          const std::string moved = out + "/" + fs::path(*image).filename().string();
          link_or_copy(*image, moved);
          *image = moved;
        }
      rows[row.case_name].push_back(std::move(row));
    }
    if (merged.mode.empty()) merged = r;
    merged.wall_s = std::max(merged.wall_s, r.wall_s);  // the shards ran side by side
  }
  merged.report_dir = out;
  merged.rows.clear();
  for (const std::string& c : shards.front().manifest.items) {
    if (!rows.count(c)) throw InputError(shards.front().dir, "merge: no shard has rows for case '" + c + "'");
    merged.rows.insert(merged.rows.end(), rows[c].begin(), rows[c].end());
  }
  bool error = false, fail = false;
  for (const GoldenRow& row : merged.rows) {
    error |= row.status == GoldenStatus::Error;
    fail |= row.status == GoldenStatus::Fail;
  }
  merged.exit_code = error ? 2 : fail ? 1 : 0;
  write_merge_record(shards, out);
  const std::string table = format_golden_report(merged);
  write_file_atomic(out + "/golden_report.txt", table);
  write_file_atomic(out + "/golden_report.json", golden_report_json(merged).dump(2) + "\n");
  std::cout << table << "report: " << out << "/golden_report.json, " << out << "/golden_report.txt\n";
  return merged.exit_code;
}

}  // namespace cr

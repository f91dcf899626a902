// merge_sweep: the shards' sweep.json rows in point order, their point
// profiles and cached references, as one sweep folder.
#include <filesystem>
#include <map>

#include "engine/cli/shard_merge.h"
#include "engine/cli/sweep_csv.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"

namespace cr {

namespace fs = std::filesystem;

int merge_sweep(const std::vector<ShardDir>& shards, const std::string& out) {
  fs::create_directories(out + "/profiles");
  fs::create_directories(out + "/references");
  std::map<std::string, nlohmann::json> rows;  // by point id
  nlohmann::json doc;
  for (const ShardDir& s : shards) {
    const std::string file = s.dir + "/sweep.json";
    if (!fs::exists(file)) throw InputError(file, "missing: the shard's sweep never wrote a point");
    nlohmann::json d = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (d.is_discarded() || !d.is_object() || !d.contains("points") || !d["points"].is_array())
      throw InputError(file, "not a sweep file");
    for (nlohmann::json& row : d["points"]) {
      const std::string id = row.value("point", "");
      if (std::find(s.manifest.owned.begin(), s.manifest.owned.end(), id) == s.manifest.owned.end())
        throw InputError(file, "point '" + id + "' is not one of shard " + s.manifest.shard.label() + "'s");
      // The point's profile, renamed into the merged folder.
      const std::string name = fs::path(row.value("profile", "")).filename().string();
      const std::string profile = s.dir + "/profiles/" + name;
      if (name.empty() || !fs::exists(profile)) throw InputError(profile, "missing: point '" + id + "''s profile");
      link_or_copy(profile, out + "/profiles/" + name);
      row["profile"] = out + "/profiles/" + name;
      rows[id] = std::move(row);
    }
    if (fs::exists(s.dir + "/references"))
      for (const fs::directory_entry& e : fs::directory_iterator(s.dir + "/references"))
        if (e.is_regular_file() && !fs::exists(out + "/references/" + e.path().filename().string()))
          link_or_copy(e.path().string(), out + "/references/" + e.path().filename().string());
    if (doc.is_null()) doc = std::move(d);
  }
  doc["points"] = nlohmann::json::array();
  for (const std::string& id : shards.front().manifest.items) {
    if (!rows.count(id)) throw InputError(shards.front().dir, "merge: no shard has a row for point '" + id + "'");
    doc["points"].push_back(rows[id]);
  }
  write_merge_record(shards, out);
  write_file_atomic(out + "/sweep.json", doc.dump(2) + "\n");
  write_file_atomic(out + "/sweep.csv", sweep_csv(doc));
  std::printf("merged %zu shards: wrote %s/sweep.json and %s/sweep.csv (%zu points)\n", shards.size(), out.c_str(),
              out.c_str(), doc["points"].size());
  return 0;
}

}  // namespace cr

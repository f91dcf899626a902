#include "engine/cli/shard_merge.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"

namespace cr {

namespace fs = std::filesystem;

namespace {

// The first top-level key whose value differs, for a message.
std::string first_difference(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_object() && b.is_object()) {
    for (const auto& [k, v] : a.items())
      if (!b.contains(k) || b.at(k) != v) return "\"" + k + "\"";
    for (const auto& [k, v] : b.items())
      if (!a.contains(k)) return "\"" + k + "\"";
  }
  return "its value";
}

}  // namespace

std::vector<ShardDir> check_shards(const std::vector<std::string>& dirs) {
  std::vector<ShardDir> shards;
  for (const std::string& d : dirs) shards.push_back({d, read_shard_manifest(d)});
  const ShardDir& a = shards.front();
  const std::string what = a.manifest.command;
  std::map<int, std::string> by_index;
  for (const ShardDir& s : shards) {
    const ShardManifest& m = s.manifest;
    const std::string file = s.dir + "/" + kShardManifestName;
    if (m.command != a.manifest.command)
      throw InputError(file, "a shard of a " + m.command + ", not of a " + what + " like " + a.dir);
    if (m.build != a.manifest.build)
      throw InputError(file, "rendered by another build than " + a.dir +
                                 " (builds may differ in their bits): rerun the shards with one build");
    if (m.definition != a.manifest.definition)
      throw InputError(file, "a different " + what + " than " + a.dir + " (its " +
                                 first_difference(a.manifest.definition, m.definition) + " differs)");
    if (m.items != a.manifest.items)
      throw InputError(file, "a different " + what + " than " + a.dir + " (other points, cases or frames)");
    if (m.shard.count != a.manifest.shard.count)
      throw InputError(file, "shard " + m.shard.label() + ", but " + a.dir + " is shard " + a.manifest.shard.label());
    if (!by_index.emplace(m.shard.index, s.dir).second)
      throw InputError(file, "shard " + m.shard.label() + " given twice (also " + by_index[m.shard.index] + ")");
    if (!m.complete)
      throw InputError(file, "shard " + m.shard.label() + " is incomplete (" + std::to_string(m.done.size()) + " of " +
                                 std::to_string(m.owned.size()) +
                                 " done): rerun it with the same command and --resume");
  }
  const int count = a.manifest.shard.count;
  std::string missing;
  for (int i = 0; i < count; ++i)
    if (!by_index.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(count);
  if (!missing.empty()) throw InputError(a.dir, "shard(s) " + missing + " missing: give every shard's folder");
  // Every item in exactly one shard.
  std::map<std::string, int> owners;
  for (const ShardDir& s : shards)
    for (const std::string& item : s.manifest.owned) ++owners[item];
  for (const std::string& item : a.manifest.items)
    if (owners[item] != 1)
      throw InputError(a.dir, "item '" + item + "' belongs to " + std::to_string(owners[item]) + " shards");
  std::sort(shards.begin(), shards.end(),
            [](const ShardDir& x, const ShardDir& y) { return x.manifest.shard.index < y.manifest.shard.index; });
  return shards;
}

void write_merge_record(const std::vector<ShardDir>& shards, const std::string& out) {
  nlohmann::json record = {{"command", shards.front().manifest.command},
                           {"build", shards.front().manifest.build},
                           {"shards", nlohmann::json::array()}};
  for (const ShardDir& s : shards)
    record["shards"].push_back({{"shard", s.manifest.shard.label()}, {"dir", s.dir}, {"host", s.manifest.host},
                                {"extra", s.manifest.extra}});
  write_file_atomic(out + "/merge.json", record.dump(2) + "\n");
}

void link_or_copy(const std::string& src, const std::string& dst) {
  std::error_code ec;
  fs::remove(dst, ec);
  fs::create_hard_link(src, dst, ec);
  if (ec) fs::copy_file(src, dst, fs::copy_options::overwrite_existing);
}

}  // namespace cr

#include "engine/cli/shard.h"

#include <unistd.h>

#include <charconv>
#include <filesystem>

#include "engine/cli/cache_key.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"

namespace cr {

std::pair<int, int> Shard::frame_block(int first, int frames) const {
  const int base = frames / count, extra = frames % count;
  const int begin = first + index * base + std::min(index, extra);
  return {begin, begin + base + (index < extra ? 1 : 0)};
}

Shard parse_shard(const std::string& text, const std::string& command) {
  const size_t slash = text.find('/');
  auto number = [&](const std::string& s, int& out) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size() && !s.empty();
  };
  Shard s;
  if (slash == std::string::npos || !number(text.substr(0, slash), s.index) ||
      !number(text.substr(slash + 1), s.count) || s.count < 1 || s.count > 65536 || s.index < 0 ||
      s.index >= s.count)
    throw UsageError(command + ": --shard wants I/N with 0 <= I < N <= 65536 (e.g. 0/4, or $SLURM_ARRAY_TASK_ID/4), got '" +
                     text + "'");
  return s;
}

void add_shard_option(ArgParser& p) {
  p.option("shard", "I/N", "render only shard I of N (0-based) and write OUT/shard.json; join with `cpurender merge`");
}

ShardOption shard_option(const ArgParser& p, const std::string& command) {
  if (!p.has("shard")) return {};
  return {parse_shard(p.get("shard"), command), true};
}

nlohmann::json ShardManifest::to_json() const {
  return {{"format", "cpurender-shard"}, {"version", 1},
          {"command", command},          {"shard", {{"index", shard.index}, {"count", shard.count}}},
          {"build", build},              {"host", host},
          {"complete", complete},        {"definition", definition},
          {"items", items},              {"owned", owned},
          {"done", done},
          {"extra", extra}};
}

ShardManifest ShardManifest::from_json(const nlohmann::json& j, const std::string& file) {
  if (!j.is_object() || j.value("format", "") != "cpurender-shard")
    throw InputError(file, "not a shard manifest (written by a command run with --shard)");
  ShardManifest m;
  try {
    m.command = j.at("command").get<std::string>();
    m.shard.index = j.at("shard").at("index").get<int>();
    m.shard.count = j.at("shard").at("count").get<int>();
    m.build = j.at("build").get<std::string>();
    m.host = j.value("host", "");
    m.complete = j.at("complete").get<bool>();
    m.definition = j.at("definition");
    m.items = j.at("items").get<std::vector<std::string>>();
    m.owned = j.at("owned").get<std::vector<std::string>>();
    m.done = j.at("done").get<std::vector<std::string>>();
    m.extra = j.value("extra", nlohmann::json::object());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed shard manifest: ") + e.what());
  }
  if (m.shard.count < 1 || m.shard.index < 0 || m.shard.index >= m.shard.count)
    throw InputError(file, "malformed shard manifest: shard " + m.shard.label());
  return m;
}

ShardManifest new_shard_manifest(const std::string& command, const Shard& shard, nlohmann::json definition) {
  ShardManifest m;
  m.command = command;
  m.shard = shard;
  m.build = build_hash();
  m.host = host_name();
  m.definition = std::move(definition);
  return m;
}

void write_shard_manifest(const std::string& dir, const ShardManifest& manifest) {
  write_file_atomic(dir + "/" + kShardManifestName, manifest.to_json().dump(2) + "\n");
}

ShardManifest read_shard_manifest(const std::string& dir) {
  const std::string file = dir + "/" + kShardManifestName;
  if (!std::filesystem::exists(file))
    throw InputError(file, "missing: not the output of a command run with --shard, or the shard never started");
  const nlohmann::json j = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
  if (j.is_discarded()) throw InputError(file, "not valid JSON");
  return ShardManifest::from_json(j, file);
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

}  // namespace cr

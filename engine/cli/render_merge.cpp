// merge_render: the shards' frame files in one folder and one report.json
// listing every frame, its summary recomputed over all of them.
#include <filesystem>
#include <iostream>

#include "engine/cli/shard_merge.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/timing_report.h"

namespace cr {

namespace fs = std::filesystem;

namespace {

// The shards' Chrome traces as one, each shard a process of its own (its
// clock starts at its own first frame): the rows a single run's trace has,
// once per shard.
void merge_traces(const std::vector<ShardDir>& shards, const std::string& out) {
  nlohmann::json events = nlohmann::json::array();
  for (size_t k = 0; k < shards.size(); ++k) {
    const std::string file = shards[k].dir + "/trace.json";
    if (!fs::exists(file)) return;  // a shard ran with --no-trace: no merged trace
    nlohmann::json trace = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (!trace.is_object() || !trace.contains("traceEvents") || !trace["traceEvents"].is_array())
      throw InputError(file, "not a Chrome trace");
    for (nlohmann::json& e : trace["traceEvents"]) {
      if (!e.is_object()) continue;
      e["pid"] = k + 1;
      if (e.value("name", "") == "process_name" && e.value("ph", "") == "M")
        e["args"]["name"] = "shard " + shards[k].manifest.shard.label() + " (" + shards[k].manifest.host + ")";
      events.push_back(std::move(e));
    }
  }
  write_file_atomic(out + "/trace.json", nlohmann::json{{"traceEvents", std::move(events)}}.dump() + "\n");
}

}  // namespace

int merge_render(const std::vector<ShardDir>& shards, const std::string& out) {
  fs::create_directories(out);
  nlohmann::json merged, frames = nlohmann::json::array(), parts = nlohmann::json::array();
  size_t files = 0;
  for (const ShardDir& s : shards) {
    const std::string file = s.dir + "/report.json";
    if (!fs::exists(file)) throw InputError(file, "missing: the shard never started");
    const nlohmann::json r = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (r.is_discarded() || !r.is_object() || r.value("format", "") != "cpurender-run-report")
      throw InputError(file, "not a run report");
    if (r.value("status", "") != "complete")
      throw InputError(file, "the shard's render is not complete (status \"" + r.value("status", "") +
                                 "\"): rerun it with --resume");
    const std::vector<std::string>& owned = s.manifest.owned;
    const nlohmann::json& listed = r.at("frames");
    if (listed.size() != owned.size())
      throw InputError(file, "lists " + std::to_string(listed.size()) + " frames, the shard owns " +
                                 std::to_string(owned.size()));
    for (size_t k = 0; k < owned.size(); ++k) {
      if (std::to_string(listed[k].value("frame", -1)) != owned[k])
        throw InputError(file, "frame " + owned[k] + " is not where the report lists it");
      char stem[64];
      std::snprintf(stem, sizeof stem, "/frame_%04d", std::stoi(owned[k]));
      for (const char* ext : {".png", ".exr"}) {
        const std::string src = s.dir + stem + ext;
        if (!fs::exists(src)) continue;
        link_or_copy(src, out + stem + ext);
        ++files;
      }
      frames.push_back(listed[k]);
    }
    const nlohmann::json& render = r.at("extra").at("render");
    parts.push_back({{"shard", s.manifest.shard.label()}, {"dir", s.dir}, {"host", s.manifest.host},
                     {"threads", r.at("threads")}, {"block", render.at("block")},
                     {"warmup_frames", render.value("warmup_frames", 0)}});
    if (merged.is_null()) merged = r;
  }
  merged["frames"] = frames;
  merged["summary"] = summarize_frames(frames, merged.at("summary").at("frame_budget_ms").get<double>());
  merged["extra"]["render"].erase("block");
  merged["extra"]["render"]["shard"] = "merged";
  merged["extra"]["render"]["shards"] = parts;
  write_merge_record(shards, out);
  merge_traces(shards, out);
  write_file_atomic(out + "/report.json", merged.dump(2) + "\n");
  std::cout << format_summary(merged) << "merged " << shards.size() << " shards: " << files << " frame files and "
            << out << "/report.json\n";
  return 0;
}

}  // namespace cr

#pragma once
// Splitting one run (a sweep, a golden check, a render) over N independent
// processes, "shards", on one machine or many (Slurm job arrays, GNU
// parallel), and the manifest each shard leaves so `cpurender merge` can
// check that the pieces belong together before it joins them.
//
// A shard owns items k with k mod N = i (sweep points, golden cases: the
// costly ones spread over all shards) or one contiguous block of frames (a
// render: each block needs the frames before it warmed up, so one block per
// shard keeps that cost once).
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/cli/arg_parser.h"

namespace cr {

struct Shard {
  int index = 0;
  int count = 1;

  bool owns(size_t item) const { return int(item % size_t(count)) == index; }
  // The block [begin, end) of frames first .. first + frames - 1 this shard
  // renders: N nearly equal contiguous blocks, the longer ones first.
  std::pair<int, int> frame_block(int first, int frames) const;
  std::string label() const { return std::to_string(index) + "/" + std::to_string(count); }
};

// "I/N" with 0 <= I < N <= 65536; UsageError naming `command` otherwise.
Shard parse_shard(const std::string& text, const std::string& command);
// --shard I/N.
void add_shard_option(ArgParser& p);
// The option's shard; {0/1, given = false} when absent.
struct ShardOption {
  Shard shard;
  bool given = false;
};
ShardOption shard_option(const ArgParser& p, const std::string& command);

// OUT/shard.json: what a shard is part of and how far it got.
struct ShardManifest {
  std::string command;              // "sweep", "golden" or "render"
  Shard shard;
  std::string build;                // build_hash(): another build may render other bits
  nlohmann::json definition;        // the whole run's inputs: equal in every shard of one run
  std::vector<std::string> items;   // every item of the whole run, in order
  std::vector<std::string> owned;   // this shard's items, in order
  std::vector<std::string> done;    // this shard's finished items
  bool complete = false;            // every owned item done
  std::string host;                 // where it ran (for the merged report)
  nlohmann::json extra = nlohmann::json::object();  // the command's own figures (render: warm-up)

  nlohmann::json to_json() const;
  static ShardManifest from_json(const nlohmann::json& j, const std::string& file);  // InputError when malformed
};

// A manifest of this build and host, nothing done yet.
ShardManifest new_shard_manifest(const std::string& command, const Shard& shard, nlohmann::json definition);

constexpr const char* kShardManifestName = "shard.json";
void write_shard_manifest(const std::string& dir, const ShardManifest& manifest);
ShardManifest read_shard_manifest(const std::string& dir);  // InputError when absent or malformed
std::string host_name();

}  // namespace cr

#pragma once
// Joining the folders of a sharded run (shard.h) into the folder one
// unsharded run would have written. `check_shards` refuses pieces that do not
// make one whole run; the merges then join each command's outputs.
#include <string>
#include <vector>

#include "engine/cli/shard.h"

namespace cr {

struct ShardDir {
  std::string dir;
  ShardManifest manifest;
};

// Reads every DIR/shard.json and checks that they are the N shards, each
// complete, of one run: same command, build, definition and items, shard
// indices 0..N-1 once each. InputError naming the folder and what differs.
std::vector<ShardDir> check_shards(const std::vector<std::string>& dirs);

// Each writes OUT's files and returns the process exit code: sweep and
// render 0; golden the check's own (0 pass, 1 a case failed, 2 a case errored).
int merge_sweep(const std::vector<ShardDir>& shards, const std::string& out);
int merge_golden(const std::vector<ShardDir>& shards, const std::string& out);
int merge_render(const std::vector<ShardDir>& shards, const std::string& out);

// OUT/merge.json: which shard ran where (the merged files themselves are
// what the unsharded run writes).
void write_merge_record(const std::vector<ShardDir>& shards, const std::string& out);

// `src` at `dst`: a hard link where the file system allows, else a copy.
void link_or_copy(const std::string& src, const std::string& dst);

}  // namespace cr

// `cpurender merge`: joins the folders of a sharded sweep, golden check or
// render (--shard I/N) into the folder the unsharded command would write.
#include <filesystem>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/shard_merge.h"
#include "engine/core/error.h"

namespace cr {

int merge_command(const std::vector<std::string>& args) {
  ArgParser p("merge", "cpurender merge SHARD_DIR... --out DIR",
              "Joins the output folders of the N shards of one `sweep`, `golden` or `render` run with\n"
              "--shard I/N (each holding a shard.json) into DIR: a sweep's rows in point order, a golden\n"
              "report's rows in case order (exit status as the check's), a render's frames and one\n"
              "report.json. Refuses, naming the folder, shards of different runs (build, command line,\n"
              "scene, profile, sweep or cases), a missing or repeated shard, and an incomplete one (rerun\n"
              "it alone with --resume).");
  p.option("out", "DIR", "the merged output folder");
  if (!p.parse(args, 1, 65536)) return 0;
  if (!p.has("out")) throw UsageError("merge: --out DIR is required");
  const std::string out = p.get("out");
  const std::vector<ShardDir> shards = check_shards(p.positional());
  std::error_code ec;
  for (const ShardDir& s : shards)
    if (std::filesystem::equivalent(s.dir, out, ec))
      throw UsageError("merge: --out " + out + " is one of the shards' folders");
  const std::string& command = shards.front().manifest.command;
  if (command == "sweep") return merge_sweep(shards, out);
  if (command == "golden") return merge_golden(shards, out);
  if (command == "render") return merge_render(shards, out);
  throw InputError(shards.front().dir + "/shard.json", "unknown command \"" + command + "\"");
}

}  // namespace cr

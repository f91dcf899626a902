// Command dispatch and the one place where errors become exit codes:
// 0 success, 1 a check failed (compare/golden), 2 usage or input error.
#include <cstdio>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/cli/compare_command.h"
#include "engine/cli/golden_command.h"
#include "engine/core/error.h"
#include "engine/cli/command_registry.h"
#include "engine/cli/module_truth.h"
#include "engine/render/plugin_registry.h"

namespace cr {

namespace {

// The engine's commands, then those the tools registered.
std::vector<CliCommand> all_commands(const PluginRegistry& registry, const CommandRegistry& tools,
                                     const ModuleTruthRegistry& truths) {
  std::vector<CliCommand> cmds = {
      {"render", "render frames of a scene to PNG/EXR with a timing report and trace",
       [&](const auto& a) { return render_command(a, registry); }},
      {"bench", "benchmark the default scene and glTF files at 1 and all threads",
       [&](const auto& a) { return bench_command(a, registry); }},
      {"sweep", "render a scene at every point of a settings sweep: cost per pass and error against a reference",
       [&](const auto& a) { return sweep_command(a, registry, truths); }},
      {"aa-error", "anti-aliasing modes: edge error against a supersampled render, cost per pass",
       [&](const auto& a) { return antialiasing_command(a, registry); }},
      {"compare", "compare two images (PNG/EXR): metrics, FLIP, pass/fail, diff image",
       [](const auto& a) { return compare_command(a); }},
      {"golden", "golden-image check of every scene and profile (1 vs N threads bit-exact); --update",
       [&](const auto& a) { return golden_command(a, registry); }},
      {"merge", "join the folders of a sharded sweep, golden check or render (--shard I/N) into one",
       [](const auto& a) { return merge_command(a); }},
  };
  for (const CliCommand& c : tools.commands()) cmds.push_back(c);
  return cmds;
}

void print_help(const std::vector<CliCommand>& cmds) {
  std::cout << "usage: cpurender <command> [options]   (cpurender <command> --help for details)\n\ncommands:\n";
  for (const CliCommand& c : cmds) {
    std::string left = "  " + c.name;
    std::cout << left << std::string(left.size() < 18 ? 18 - left.size() : 1, ' ') << c.summary << "\n";
  }
}

}  // namespace

int run_cli(int argc, char** argv,
            const std::function<void(PluginRegistry&, CommandRegistry&, ModuleTruthRegistry&)>& register_builtins) {
  PluginRegistry registry;
  CommandRegistry tools;
  ModuleTruthRegistry truths;
  try {
    register_builtins(registry, tools, truths);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cpurender: internal error registering plugins: %s\n", e.what());
    return 2;
  }
  const std::vector<CliCommand> cmds = all_commands(registry, tools, truths);
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    print_help(cmds);
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const CliCommand& c : cmds) {
    if (c.name != name) continue;
    try {
      return c.run(args);
    } catch (const UsageError& e) {
      std::fprintf(stderr, "cpurender %s\n(see cpurender %s --help)\n", e.what(), name.c_str());
      return 2;
    } catch (const InputError& e) {
      std::fprintf(stderr, "cpurender: error: %s\n", e.what());
      return 2;
    } catch (const std::bad_alloc&) {
      // Estimates (--memory-limit) cover what inputs ask for; this is what they missed.
      std::fprintf(stderr,
                   "cpurender: error: out of memory: an allocation failed although the run's estimate was within "
                   "--memory-limit; lower the resolution, anti-aliasing, LUT, froxel or texture sizes\n");
      return 2;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cpurender: error: %s\n", e.what());
      return 2;
    }
  }
  std::fprintf(stderr, "cpurender: unknown command '%s' (see cpurender --help)\n", name.c_str());
  return 2;
}

}  // namespace cr

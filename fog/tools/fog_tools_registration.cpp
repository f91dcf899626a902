#include "engine/cli/command_registry.h"
#include "fog/tools/fog_commands.h"
#include "fog/tools/fog_truth.h"

namespace cr {

namespace {

// A command bound to the plugin registry it renders with; the CLI turns its
// errors into one message and exit code 2 like every other command's.
CliCommand command(const char* name, const char* summary, const PluginRegistry& plugins,
                   int (*run)(const std::vector<std::string>&, const PluginRegistry&)) {
  return CliCommand{name, summary, [&plugins, run](const std::vector<std::string>& args) { return run(args, plugins); }};
}

}  // namespace

void register_fog_commands(CommandRegistry& commands, ModuleTruthRegistry& truths, const PluginRegistry& plugins) {
  commands.add(command("fog-accuracy", "froxel fog vs per-pixel ray-marched reference: error and time", plugins,
                       fog_accuracy_command));
  commands.add(command("fog-temporal", "fog ghosting on a fast camera path and temporal noise when static", plugins,
                       fog_temporal_command));
  commands.add(command("fog-bench", "fog pass times at the profile's resolution, 1 and all threads", plugins,
                       fog_bench_command));
  commands.add(command("fog-stability", "fog error map over extinction, g, camera speed and history weight; rejection",
                       plugins, fog_stability_command));
  truths.add(fog_truth(plugins));
}

}  // namespace cr

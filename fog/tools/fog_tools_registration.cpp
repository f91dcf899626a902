#include "fog/fog_commands.h"
#include "fog/fog_plugin.h"

namespace cr {

namespace {

// A command bound to the registry; the CLI turns its errors into one message
// and exit code 2 like every other command's.
PluginCommand command(const char* name, const char* summary, const PluginRegistry& registry,
                      int (*run)(const std::vector<std::string>&, const PluginRegistry&)) {
  return PluginCommand{name, summary,
                       [&registry, run](const std::vector<std::string>& args) { return run(args, registry); }};
}

}  // namespace

void register_fog_plugin(PluginRegistry& registry) {
  registry.add("fog", [] { return std::make_unique<FogPlugin>(); });
  registry.add_command(command("fog-accuracy", "froxel fog vs per-pixel ray-marched reference: error and time",
                               registry, fog_accuracy_command));
  registry.add_command(command("fog-temporal", "fog ghosting on a fast camera path and temporal noise when static",
                               registry, fog_temporal_command));
  registry.add_command(command("fog-bench", "fog pass times at the profile's resolution, 1 and all threads", registry,
                               fog_bench_command));
}

}  // namespace cr

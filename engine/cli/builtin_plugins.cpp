// The plugins linked into cpurender and their tools. This file is the
// composition root: the engine libraries never name a plugin.
#include "atmosphere/atmosphere_plugin.h"
#include "atmosphere/tools/sky_commands.h"
#include "engine/cli/commands.h"
#include "engine/render/plugin_registry.h"
#include "fog/fog_plugin.h"
#include "fog/tools/fog_commands.h"

namespace cr {

void register_builtin_plugins(PluginRegistry& plugins) {
  register_atmosphere_plugin(plugins);
  register_fog_plugin(plugins);
}

void register_builtin_tools(CommandRegistry& commands, ModuleTruthRegistry& truths, const PluginRegistry& plugins) {
  register_sky_commands(commands, truths);
  register_fog_commands(commands, truths, plugins);
}

}  // namespace cr

// The plugins linked into cpurender. This file is the composition root: the
// engine libraries never name a plugin.
#include "atmosphere/atmosphere_plugin.h"
#include "engine/cli/commands.h"
#include "fog/fog_plugin.h"

namespace cr {

void register_builtin_plugins(PluginRegistry& registry) {
  register_atmosphere_plugin(registry);
  register_fog_plugin(registry);
}

}  // namespace cr

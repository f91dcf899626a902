#pragma once
// The CLI's commands: render, bench, compare, ... Each returns a process exit
// code and prints one clear message on error.
#include <functional>

namespace cr {

class PluginRegistry;

// Registers the plugins linked into this binary (atmosphere, fog); defined by
// the composition root (builtin_plugins.cpp), not by the engine.
void register_builtin_plugins(PluginRegistry& registry);
// Runs the CLI with the plugins that `register_plugins` registers.
int run_cli(int argc, char** argv, const std::function<void(PluginRegistry&)>& register_plugins);

}  // namespace cr

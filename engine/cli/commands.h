#pragma once
// The CLI's commands: render, bench, compare, ... Each returns a process exit
// code and prints one clear message on error.
namespace cr {

class PluginRegistry;

// Registers the plugins linked into this binary (atmosphere, fog).
void register_builtin_plugins(PluginRegistry& registry);
int run_cli(int argc, char** argv);

}  // namespace cr

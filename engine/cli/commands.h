#pragma once
// The CLI's entry points. Each command returns a process exit code and prints
// one clear message on error.
#include <functional>

namespace cr {

class CommandRegistry;
class ModuleTruthRegistry;
class PluginRegistry;

// The plugins linked into this binary (atmosphere, fog) and their tools'
// commands (sky-*, fog-*, which render through `plugins`) and ground truths
// (for sweep --truth); defined by the composition root (builtin_plugins.cpp),
// not by the engine.
void register_builtin_plugins(PluginRegistry& plugins);
void register_builtin_tools(CommandRegistry& commands, ModuleTruthRegistry& truths, const PluginRegistry& plugins);
// Runs the CLI with the plugins, tool commands and module truths that `register_builtins` adds.
int run_cli(int argc, char** argv,
            const std::function<void(PluginRegistry&, CommandRegistry&, ModuleTruthRegistry&)>& register_builtins);

}  // namespace cr

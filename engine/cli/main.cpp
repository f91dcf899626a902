// cpurender: the command-line entry point. Plugins are registered here, the
// composition root; the engine itself knows none of them.
#include "engine/cli/commands.h"

int main(int argc, char** argv) { return cr::run_cli(argc, argv, cr::register_builtin_plugins); }

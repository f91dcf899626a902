// cpurender: the command-line entry point. Plugins are registered here, the
// composition root; the engine itself knows none of them.
#include <cstdio>
#include <cstdlib>

#include "engine/cli/commands.h"

#ifdef CR_ARCH_LEVEL
namespace {
// Runs before other constructors (priority 101): the rest of the program is
// built for CR_ARCH_LEVEL and may use its instructions anywhere.
__attribute__((constructor(101))) void require_instruction_set() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports(CR_ARCH_LEVEL)) return;
  std::fprintf(stderr,
               "cpurender: error: this binary was built for %s, which this CPU does not support; "
               "rebuild with cmake -DCR_ARCH=x86-64-v2 (or x86-64)\n",
               CR_ARCH_LEVEL);
  std::exit(1);
}
}  // namespace
#endif

int main(int argc, char** argv) {
  return cr::run_cli(argc, argv, [](cr::PluginRegistry& plugins, cr::CommandRegistry& commands,
                                    cr::ModuleTruthRegistry& truths) {
    cr::register_builtin_plugins(plugins);
    cr::register_builtin_tools(commands, truths, plugins);
  });
}

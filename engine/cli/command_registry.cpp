#include "engine/cli/command_registry.h"

#include "engine/core/error.h"

namespace cr {

void CommandRegistry::add(CliCommand command) {
  for (const CliCommand& c : commands_)
    if (c.name == command.name) throw Error("command '" + command.name + "' registered twice");
  commands_.push_back(std::move(command));
}

}  // namespace cr

#pragma once
// The CLI's command table. The engine's commands (render, bench, ...) and
// those a plugin's tools contribute (sky-accuracy, fog-bench, ...) are added
// by the composition root; the runtime libraries know none of them.
#include <functional>
#include <string>
#include <vector>

namespace cr {

// `run` gets the arguments after the command name and returns the process
// exit code; it throws UsageError or InputError for the CLI to report.
struct CliCommand {
  std::string name;
  std::string summary;  // one line for `cpurender --help`
  std::function<int(const std::vector<std::string>& args)> run;
};

class CommandRegistry {
 public:
  void add(CliCommand command);  // throws Error on a name added twice
  const std::vector<CliCommand>& commands() const { return commands_; }

 private:
  std::vector<CliCommand> commands_;
};

}  // namespace cr

#pragma once
// A small strict command-line parser: declared options only, typed values,
// one clear error for anything else, and generated --help text.
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace cr {

class ArgParser {
 public:
  ArgParser(std::string command, std::string usage, std::string description);
  // An option taking a value ("--frames N"); `metavar` names the value in help.
  ArgParser& option(const std::string& name, const std::string& metavar, const std::string& help,
                    std::optional<std::string> default_value = std::nullopt);
  ArgParser& flag(const std::string& name, const std::string& help);
  // Parses args (after the command name). Throws UsageError on unknown options,
  // missing values or too many/few positionals. Returns false for --help
  // (help text already printed).
  bool parse(const std::vector<std::string>& args, size_t min_positional, size_t max_positional);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const;  // option given or defaulted, or flag set
  std::string get(const std::string& name) const;  // the last value given
  // Every value given for a repeatable option, in order (empty when none; defaults are not included).
  std::vector<std::string> get_all(const std::string& name) const;
  // A comma-separated value split into its items ("png,exr" -> png, exr).
  std::vector<std::string> get_list(const std::string& name) const;
  int get_int(const std::string& name, int min, int max) const;
  double get_double(const std::string& name, double min, double max) const;
  // A non-empty comma-separated list of numbers, each in [min, max] ("0,45,80").
  std::vector<double> get_doubles(const std::string& name, double min, double max) const;
  std::string help() const;

 private:
  struct Spec {
    std::string metavar, help;
    std::optional<std::string> default_value;
    bool is_flag = false;
  };
  std::string command_, usage_, description_;
  std::vector<std::string> order_;
  std::map<std::string, Spec> specs_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> every_value_;
  std::vector<std::string> positional_;
};

// Command-line misuse: printed with a hint to --help, exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cr

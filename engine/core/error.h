#pragma once
// Errors the engine reports to the user. An InputError names the offending file
// and what is wrong with it, so the CLI can print one clear line and exit non-zero.
#include <stdexcept>
#include <string>

namespace cr {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  InputError(const std::string& file, const std::string& what)
      : Error(file + ": " + what), file_(file) {}
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace cr

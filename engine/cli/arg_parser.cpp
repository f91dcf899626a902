#include "engine/cli/arg_parser.h"

#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace cr {

ArgParser::ArgParser(std::string command, std::string usage, std::string description)
    : command_(std::move(command)), usage_(std::move(usage)), description_(std::move(description)) {}

ArgParser& ArgParser::option(const std::string& name, const std::string& metavar, const std::string& help,
                             std::optional<std::string> default_value) {
  order_.push_back(name);
  specs_[name] = Spec{metavar, help, std::move(default_value), false};
  return *this;
}

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
  order_.push_back(name);
  specs_[name] = Spec{"", help, std::nullopt, true};
  return *this;
}

bool ArgParser::parse(const std::vector<std::string>& args, size_t min_positional, size_t max_positional) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::cout << help();
      return false;
    }
    if (a.rfind("--", 0) == 0) {
      std::string name = a.substr(2), value;
      const size_t eq = name.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      auto it = specs_.find(name);
      if (it == specs_.end()) throw UsageError(command_ + ": unknown option --" + name);
      if (it->second.is_flag) {
        if (inline_value) throw UsageError(command_ + ": --" + name + " takes no value");
        values_.insert_or_assign(name, std::string("1"));
      } else {
        if (!inline_value) {
          // A following option is not a value: "--resolution --out DIR" lacks the resolution.
          if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
            throw UsageError(command_ + ": --" + name + " needs a value (" + it->second.metavar + ")");
          value = args[++i];
        }
        if (value.empty()) throw UsageError(command_ + ": --" + name + " needs a value (" + it->second.metavar + "), got ''");
        values_[name] = value;
        every_value_[name].push_back(value);
      }
    } else {
      positional_.push_back(a);
    }
  }
  if (positional_.size() < min_positional)
    throw UsageError(command_ + ": missing argument; usage: " + usage_);
  if (positional_.size() > max_positional)
    throw UsageError(command_ + ": unexpected argument '" + positional_[max_positional] + "'; usage: " + usage_);
  return true;
}

bool ArgParser::has(const std::string& name) const {
  if (values_.count(name)) return true;
  auto it = specs_.find(name);
  return it != specs_.end() && it->second.default_value.has_value();
}

std::vector<std::string> ArgParser::get_all(const std::string& name) const {
  auto v = every_value_.find(name);
  return v == every_value_.end() ? std::vector<std::string>{} : v->second;
}

std::string ArgParser::get(const std::string& name) const {
  auto v = values_.find(name);
  if (v != values_.end()) return v->second;
  auto it = specs_.find(name);
  if (it != specs_.end() && it->second.default_value) return *it->second.default_value;
  throw std::logic_error("ArgParser: option --" + name + " not given and has no default");
}

std::vector<std::string> ArgParser::get_list(const std::string& name) const {
  std::vector<std::string> items;
  std::stringstream ss(get(name));
  for (std::string item; std::getline(ss, item, ',');) items.push_back(item);
  return items;
}

int ArgParser::get_int(const std::string& name, int min, int max) const {
  const std::string s = get(name);
  size_t used = 0;
  long v = 0;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty()) throw UsageError(command_ + ": --" + name + " expects an integer, got '" + s + "'");
  if (v < min || v > max)
    throw UsageError(command_ + ": --" + name + " must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " + s);
  return int(v);
}

namespace {

// The whole of `s` as a finite number, or nothing.
std::optional<double> parse_number(const std::string& s) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || s.empty() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::vector<double> ArgParser::get_doubles(const std::string& name, double min, double max) const {
  std::vector<double> values;
  for (const std::string& item : get_list(name)) {
    const std::optional<double> v = parse_number(item);
    if (!v) throw UsageError(command_ + ": --" + name + " expects comma-separated numbers, got '" + item + "'");
    if (*v < min || *v > max) throw UsageError(command_ + ": --" + name + " is out of range: " + item);
    values.push_back(*v);
  }
  if (values.empty()) throw UsageError(command_ + ": --" + name + " is empty");
  return values;
}

double ArgParser::get_double(const std::string& name, double min, double max) const {
  const std::string s = get(name);
  const std::optional<double> v = parse_number(s);
  if (!v) throw UsageError(command_ + ": --" + name + " expects a number, got '" + s + "'");
  if (*v < min || *v > max) throw UsageError(command_ + ": --" + name + " is out of range: " + s);
  return *v;
}

std::string ArgParser::help() const {
  std::ostringstream o;
  o << "usage: " << usage_ << "\n\n" << description_ << "\n\noptions:\n";
  for (const std::string& name : order_) {
    const Spec& s = specs_.at(name);
    std::string left = "  --" + name + (s.is_flag ? "" : " " + s.metavar);
    o << left;
    o << std::string(left.size() < 30 ? 30 - left.size() : 1, ' ') << s.help;
    if (s.default_value) o << " (default: " << *s.default_value << ")";
    o << "\n";
  }
  o << "  --help                      show this help\n";
  return o.str();
}

}  // namespace cr

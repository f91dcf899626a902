#pragma once
// The plugins a program links: a factory per plugin name. The composition
// root (the CLI's builtin_plugins.cpp) adds them; a Renderer gets one
// instance of each and keeps those the scene uses.
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/render/plugin.h"

namespace cr {

class PluginRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Plugin>()>;
  void add(const std::string& name, Factory factory);  // throws Error on a name added twice
  std::vector<std::string> names() const;
  std::vector<std::unique_ptr<Plugin>> create_all() const;

 private:
  std::vector<std::pair<std::string, Factory>> factories_;
};

}  // namespace cr

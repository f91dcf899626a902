#include "engine/core/error.h"
#include "engine/render/plugin_registry.h"

namespace cr {

void PluginRegistry::add(const std::string& name, Factory factory) {
  for (const auto& [n, f] : factories_)
    if (n == name) throw Error("plugin '" + name + "' registered twice");
  factories_.emplace_back(name, std::move(factory));
}

std::vector<std::string> PluginRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [n, f] : factories_) v.push_back(n);
  return v;
}

std::vector<std::unique_ptr<Plugin>> PluginRegistry::create_all() const {
  std::vector<std::unique_ptr<Plugin>> v;
  for (const auto& [n, f] : factories_) v.push_back(f());
  return v;
}

}  // namespace cr

#include "engine/core/profile_keys.h"

#include <vector>

#include "engine/core/error.h"

namespace cr {

namespace {

std::vector<std::string> key_path(const std::string& key) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (true) {
    const size_t end = key.find('.', begin);
    parts.push_back(key.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) return parts;
    begin = end + 1;
  }
}

}  // namespace

void set_profile_key(nlohmann::json& profile, const std::string& key, const nlohmann::json& value) {
  nlohmann::json* node = &profile;
  const std::vector<std::string> path = key_path(key);
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    if (!node->is_object()) throw InputError(key, "a key on its path is not an object in the profile");
    node = &(*node)[path[i]];
    if (node->is_null()) *node = nlohmann::json::object();
  }
  if (!node->is_object()) throw InputError(key, "its parent is not an object in the profile");
  (*node)[path.back()] = value;
}

nlohmann::json profile_key(const nlohmann::json& profile, const std::string& key) {
  const nlohmann::json* node = &profile;
  for (const std::string& part : key_path(key)) {
    if (!node->is_object() || !node->contains(part)) return nullptr;
    node = &(*node)[part];
  }
  return *node;
}

}  // namespace cr

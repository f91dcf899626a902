#include "engine/cli/paths.h"

#include <cstdlib>
#include <filesystem>

namespace cr {

std::string executable_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

std::string resolve_profile_path(const std::string& name_or_path) {
  const bool is_path = name_or_path.find('/') != std::string::npos ||
                       std::filesystem::path(name_or_path).extension() == ".json";
  if (is_path) return name_or_path;
  return executable_dir() + "/profiles/" + name_or_path + ".json";
}

std::string default_scene_path() { return executable_dir() + "/scenes/default.json"; }

std::vector<std::string> scene_asset_dirs() {
  std::vector<std::string> dirs = {executable_dir() + "/scenes"};
  if (const char* assets = std::getenv("CR_ASSETS_DIR"); assets && *assets) dirs.push_back(assets);
  return dirs;
}

}  // namespace cr

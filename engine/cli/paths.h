#pragma once
// Where the CLI finds its shipped data: profiles/ and scenes/ are copied next
// to the executable by the build, so `cpurender render` works from anywhere.
#include <string>

namespace cr {

std::string executable_dir();
// A profile given by name ("desktop") or by path ("my/profile.json").
std::string resolve_profile_path(const std::string& name_or_path);
// The default scene (<exe dir>/scenes/default.json).
std::string default_scene_path();

}  // namespace cr

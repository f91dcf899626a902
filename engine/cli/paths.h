#pragma once
// Where the CLI finds its shipped data: profiles/ and scenes/ are copied next
// to the executable by the build, so `cpurender render` works from anywhere.
#include <string>
#include <vector>

namespace cr {

std::string executable_dir();
// A profile given by name ("desktop") or by path ("my/profile.json").
std::string resolve_profile_path(const std::string& name_or_path);
// The default scene (<exe dir>/scenes/default.json).
std::string default_scene_path();

// Where a scene file's relative "gltf" path is looked up after the scene
// file's own folder: the executable's scenes/ (the generated default.glb)
// and, when set, $CR_ASSETS_DIR (third-party models, README "Third-party models").
std::vector<std::string> scene_asset_dirs();

}  // namespace cr

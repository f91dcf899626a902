// libFuzzer target: scene file JSON -> cr::load_scene_description with the
// built-in plugins' sections ("atmosphere", "fog"), then those sections
// through the plugins' own validation, as AtmospherePlugin::configure and
// FogPlugin::configure run it (parse_atmosphere_scene, parse_fog_scene and
// resolve_fog_settings against the default profile settings).
// The bytes are written to <scratch>/scene.json. The scratch folder holds
// empty default.glb and model.gltf, and assets/asset.glb is found through
// the asset folder list (as the CLI passes the build's scenes/), so a "gltf"
// key naming them passes and the keys after it are read.
#include <filesystem>
#include <string>
#include <vector>

#include "atmosphere/atmosphere_model.h"
#include "engine/scene/scene_description.h"
#include "fog/fog_settings.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

const std::vector<std::string> kPluginSections = {"atmosphere", "fog"};
std::vector<std::string> g_asset_dirs;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const std::string& dir = cr::fuzz::scratch_dir();
  cr::fuzz::write_scratch_file("default.glb", nullptr, 0);
  cr::fuzz::write_scratch_file("model.gltf", nullptr, 0);
  std::filesystem::create_directory(dir + "/assets");
  cr::fuzz::write_scratch_file("assets/asset.glb", nullptr, 0);
  g_asset_dirs = {dir + "/assets"};
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cr::fuzz::write_scratch_file("scene.json", data, size);
  cr::fuzz::run_one("scene", [&] {
    const cr::SceneDescription d = cr::load_scene_description(path, kPluginSections, g_asset_dirs);
    (void)cr::emissive_luminance(d);
    if (d.animation) (void)d.animation->time_at(d.frames - 1);
    auto atmosphere = d.plugins.find("atmosphere");
    if (atmosphere != d.plugins.end() && !atmosphere->is_null()) (void)cr::parse_atmosphere_scene(*atmosphere, d.path);
    if (d.plugins.contains("fog")) {
      const cr::FogSceneSettings fog = cr::parse_fog_scene(d.plugins.at("fog"), d.path);
      (void)cr::resolve_fog_settings(cr::FogProfileSettings{}, fog);
    }
  });
  return 0;
}

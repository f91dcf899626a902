// libFuzzer target: glTF / GLB bytes -> cr::load_gltf, then each animation (up to 4)
// posed at half its duration (pose_scene: sampling, morphing, skinning).
// The bytes are written to <scratch>/model.glb when they start with the GLB
// magic "glTF", else to <scratch>/model.gltf. The scratch folder also holds
// b.bin (256 bytes) and t.png (a 2x2 RGBA image), so URIs naming them reach
// the external-file paths (the dictionary gltf.dict has both names).
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "engine/core/memory_budget.h"
#include "engine/scene/gltf_loader.h"
#include "engine/scene/scene_animation.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

void write_side_files() {
  std::vector<uint8_t> bin(256);
  for (size_t i = 0; i < bin.size(); ++i) bin[i] = uint8_t(i * 37u + 11u);
  cr::fuzz::write_scratch_file("b.bin", bin.data(), bin.size());
  const uint8_t rgba[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
  const std::string png = cr::fuzz::scratch_dir() + "/t.png";
  stbi_write_png(png.c_str(), 2, 2, 4, rgba, 8);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  write_side_files();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = cr::fuzz::write_scratch_file(glb ? "model.glb" : "model.gltf", data, size);
  cr::fuzz::run_one("gltf", [&] {
    cr::MemoryBudget budget(cr::fuzz::kMemoryBudgetBytes);
    cr::GltfLoadOptions options;
    cr::fuzz::attach_budget(options, budget);
    cr::Scene scene = cr::load_gltf(path, options);
    if (scene.animation) {
      const std::shared_ptr<const cr::SceneAnimation> animation = scene.animation;
      for (size_t a = 0; a < animation->animations.size() && a < 4; ++a) {
        cr::pose_scene(scene, *animation, a, animation->animations[a].duration_s * 0.5);
      }
    }
  });
  return 0;
}

// Every Khronos sample model of the shared assets (khronos/README.md), in
// every variant it ships (glTF, glTF-Binary, glTF-Draco, glTF-Quantized),
// loads and renders a finite frame in which the model covers pixels, from
// the automatic three-quarter view. What each model tests is asserted in the
// tests of its feature; this one guards the whole set against refusals.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"
#include "tests/khronos_assets.h"

namespace fs = std::filesystem;

TEST_CASE("every Khronos sample model in every variant loads and renders a finite, covered frame") {
  const auto root = cr::test::asset_path("khronos");
  if (!root) return;
  std::vector<fs::path> files;
  for (const fs::directory_entry& model : fs::directory_iterator(*root)) {
    if (!model.is_directory()) continue;
    for (const char* variant : {"glTF", "glTF-Binary", "glTF-Draco", "glTF-Quantized"}) {
      const fs::path dir = model.path() / variant;
      if (!fs::is_directory(dir)) continue;
      for (const fs::directory_entry& f : fs::directory_iterator(dir))
        if (f.path().extension() == ".gltf" || f.path().extension() == ".glb") files.push_back(f.path());
    }
  }
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 27);
  cr::Profile profile = cr::load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  profile.width = 96;
  profile.height = 64;
  profile.shadow_map_size = 256;
  cr::JobSystem jobs(2);
  for (const fs::path& file : files) {
    const std::string name = file.string();
    CAPTURE(name);
    cr::Scene scene;
    try {
      scene = cr::load_gltf(file.string());
    } catch (const cr::InputError& e) {
      const std::string why = e.what();
      FAIL_CHECK("refused: " << why);
      continue;
    }
    CHECK(scene.triangle_count() > 0);
    cr::SceneDescription d = cr::load_scene_description(file.string(), {});
    d.camera.auto_frame = true;
    cr::Renderer r(scene, d, profile, {}, jobs);
    r.render_frame(0);
    size_t covered = 0, finite = 0;
    const cr::FrameBuffers& b = r.buffers();
    for (size_t i = 0; i < b.color.size(); ++i) {
      covered += b.depth[i] > 0.0f;
      finite += std::isfinite(b.color[i].r) && std::isfinite(b.color[i].g) && std::isfinite(b.color[i].b);
    }
    CHECK(finite == b.color.size());
    CHECK(covered > b.color.size() / 50);
  }
}

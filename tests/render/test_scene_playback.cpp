// A camera path running an animation (scene key animation.fps): frame f of
// the playback is the still pose at time + f / fps, bit for bit, and the
// pose really changes from frame to frame (Khronos Fox, "Run").
#include <doctest/doctest.h>

#include <cstring>
#include <fstream>

#include "engine/cli/cli_common.h"
#include "tests/khronos_assets.h"

namespace {

std::string write_scene(const std::string& name, const std::string& gltf, const std::string& animation,
                        const std::string& camera = R"({"position": [150, 60, 200], "target": [0, 40, 0]})") {
  const std::string file = std::string(CR_BINARY_DIR) + "/" + name;
  std::ofstream(file) << R"({"gltf": ")" << gltf << R"(", "camera": )" << camera << R"(,
    "sun": {"azimuth_deg": 60, "elevation_deg": 40}, "ambient": [3000, 3000, 3000], "frames": 4,
    "animation": )" << animation << "}";
  return file;
}

cr::RunSetup load(const std::string& scene_file) {
  // The profile's plugin sections need their names registered; no plugin is created.
  cr::PluginRegistry sections;
  for (const char* name : {"atmosphere", "fog"}) sections.add(name, [] { return std::unique_ptr<cr::Plugin>(); });
  // One literal, not string + literal: GCC 12 -O3 warns falsely (-Warray-bounds) on the latter here in a unity build.
  return cr::load_run(scene_file, CR_SOURCE_DIR "/profiles/desktop.json",
                      sections, 96, 64, 2);
}

// The colour of the scene's frame `last` (frames 0..last rendered in order).
std::vector<glm::vec3> render(const std::string& scene_file, int last) {
  const cr::RunSetup setup = load(scene_file);
  cr::JobSystem jobs(2);
  cr::Renderer r(*setup.scene, setup.description, setup.profile, {}, jobs);
  cr::attach_playback(r, setup);
  for (int f = 0; f <= last; ++f) r.render_frame(f);
  return r.buffers().color;
}

bool same(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

}  // namespace

TEST_CASE("playback: frame f of an animation at fps equals the still pose at time + f / fps") {
  const auto gltf = cr::test::asset_path("khronos/Fox/glTF/Fox.gltf");
  if (!gltf) return;
  const std::string playing = write_scene("fox_playing.json", *gltf, R"({"name": "Run", "time": 0.1, "fps": 5})");
  const std::vector<glm::vec3> third = render(playing, 3);
  // 0.1 + 3 / 5 = 0.7 s.
  const std::string still = write_scene("fox_still.json", *gltf, R"({"name": "Run", "time": 0.7})");
  CHECK(same(third, render(still, 0)));
  CHECK_FALSE(same(third, render(playing, 0)));
  CHECK_FALSE(same(render(playing, 1), render(playing, 0)));
}

TEST_CASE("playback: the automatic view frames the described pose and holds still while the scene moves") {
  const auto gltf = cr::test::asset_path("khronos/Fox/glTF/Fox.gltf");
  if (!gltf) return;
  const cr::RunSetup setup =
      load(write_scene("fox_auto.json", *gltf, R"({"name": "Run", "time": 0.1, "fps": 5})", R"({"auto": true})"));
  cr::JobSystem jobs(2);
  cr::Renderer r(*setup.scene, setup.description, setup.profile, {}, jobs);
  cr::attach_playback(r, setup);
  const glm::dvec3 first = r.frame_view(0).camera.position;
  r.render_frame(0);
  const glm::vec3 bounds_at_0 = setup.scene->bounds_max;
  r.render_frame(1);
  r.render_frame(2);
  CHECK(setup.scene->bounds_max != bounds_at_0);  // the pose moved
  CHECK(r.frame_view(2).camera.position == first);
  const cr::FrameRecord& rec = r.render_frame(3);
  REQUIRE_FALSE(rec.passes.empty());
  CHECK(rec.passes.front().name == "pose");  // playback's cost is in the report
}

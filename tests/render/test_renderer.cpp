// Whole frames through the renderer: determinism across thread counts, frame
// graph culling, reports, camera paths, and an image-difference check.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/output/image_compare.h"
#include "engine/render/frame_view.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"

namespace {

struct Loaded {
  cr::SceneDescription description;
  cr::Profile profile;
  cr::Scene scene;
};

Loaded load(const std::string& scene_file, int w, int h) {
  Loaded l;
  l.description = cr::load_scene_description(scene_file, {});
  l.profile = cr::load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  l.profile.width = w;
  l.profile.height = h;
  l.scene = cr::load_gltf(l.description.gltf_path);
  return l;
}

// The village without plugins: this area tests the engine alone.
const std::string kDefaultScene = std::string(CR_BINARY_DIR) + "/scenes/engine_only.json";
const std::string kBox = std::string(CR_ASSIMP_GLTF_DIR) + "/BoxTextured-glTF/BoxTextured.gltf";

std::vector<glm::vec3> render_colour(const Loaded& l, unsigned threads, int frames = 1) {
  cr::JobSystem jobs(threads);
  cr::Renderer r(l.scene, l.description, l.profile, {}, jobs);
  for (int f = 0; f < frames; ++f) r.render_frame(f);
  return r.buffers().color;
}

bool bit_identical(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

}  // namespace

TEST_CASE("determinism: a frame of the default scene is bit-identical for 1, 2, 3 and 8 threads") {
  REQUIRE(std::filesystem::exists(kDefaultScene));
  const Loaded l = load(kDefaultScene, 192, 108);
  const auto one = render_colour(l, 1);
  for (unsigned t : {2u, 3u, 8u}) CHECK(bit_identical(one, render_colour(l, t)));
  CHECK(bit_identical(one, render_colour(l, 1)));  // and across runs
}

TEST_CASE("renderer culls what the scene does not need and reports every pass") {
  const Loaded l = load(kBox, 64, 48);
  cr::JobSystem jobs(2);
  cr::Renderer r(l.scene, l.description, l.profile, {}, jobs);
  const cr::FrameRecord& rec = r.render_frame(0);
  std::vector<std::string> names;
  for (const auto& p : rec.passes) names.push_back(p.name);
  // The box has no blended material and no plugin: no transparent or composite pass exists.
  CHECK(std::find(names.begin(), names.end(), "transparent") == names.end());
  CHECK(std::find(names.begin(), names.end(), "composite") == names.end());
  for (const char* required : {"light", "shadow", "geometry", "shade", "resolve"})
    CHECK(std::find(names.begin(), names.end(), required) != names.end());
  CHECK(rec.frame_ms > 0.0);
  CHECK(!rec.jobs.empty());
  CHECK(rec.raster["pixels_shaded"].get<uint64_t>() > 0);
  CHECK_THROWS_AS(r.render_frame(0), cr::Error);  // frames go forwards only
}

TEST_CASE("a static camera re-uses the shadow map and renders identical frames") {
  const Loaded l = load(kBox, 64, 48);
  cr::JobSystem jobs(2);
  cr::Renderer r(l.scene, l.description, l.profile, {}, jobs);
  r.render_frame(0);
  const auto first = r.buffers().color;
  const cr::FrameRecord& rec = r.render_frame(1);
  CHECK(rec.raster["shadow_map_reused"].get<bool>());
  CHECK(bit_identical(first, r.buffers().color));
  CHECK(r.previous_shadow_map().size == 0);  // nothing moved: no previous map to compare against
}

TEST_CASE("a moving sun keeps last frame's shadow map as the previous one") {
  Loaded l = load(kBox, 64, 48);
  l.description.sun.keys = {cr::SunKey{0, 30.0f, 50.0f}, cr::SunKey{2, 40.0f, 50.0f}};
  cr::JobSystem jobs(2);
  cr::Renderer r(l.scene, l.description, l.profile, {}, jobs);
  r.render_frame(0);
  CHECK(r.previous_shadow_map().size == 0);  // no frame before
  const cr::ShadowMap first = r.shadow_map();
  r.render_frame(1);
  const cr::ShadowMap& previous = r.previous_shadow_map();
  REQUIRE(previous.size == first.size);
  CHECK(previous.direction_to_sun == first.direction_to_sun);
  CHECK(previous.direction_to_sun != r.shadow_map().direction_to_sun);
  CHECK(previous.depth == first.depth);
  CHECK(r.shadow_map().depth != first.depth);
  const cr::ShadowMap second = r.shadow_map();
  r.render_frame(2);  // the third map renders into the first one's memory; frame 1's is previous now
  CHECK(r.previous_shadow_map().direction_to_sun == second.direction_to_sun);
  CHECK(r.previous_shadow_map().depth == second.depth);
}

TEST_CASE("a moving camera scrolls the shadow map: 1 and 3 threads agree bit for bit, and a cold frame nearly") {
  Loaded l = load(kDefaultScene, 160, 90);
  l.description.camera.gltf_camera.reset();
  cr::CameraKey a, b;
  a.position = {0, 5.0, 14};
  a.target = {0, 0.6, -96};
  b.frame = 6;
  b.position = {4, 6.5, 2};
  b.target = {-20, 1.5, -90};
  l.description.camera.keys = {a, b};
  std::vector<glm::vec3> last[2];
  for (unsigned threads : {1u, 3u}) {
    cr::JobSystem jobs(threads);
    cr::Renderer r(l.scene, l.description, l.profile, {}, jobs);
    int scrolled = 0;
    for (int f = 0; f <= 6; ++f) scrolled += r.render_frame(f).raster["shadow_map_scrolled"].get<bool>();
    CHECK(scrolled == 6);  // only the first frame renders the whole map
    last[threads == 3u] = r.buffers().color;
  }
  CHECK(bit_identical(last[0], last[1]));
  // A cold render of the last frame fits its map around that frame: the
  // same texel grid, another depth origin, so shadows agree to rounding.
  cr::JobSystem jobs(2);
  cr::Renderer cold(l.scene, l.description, l.profile, {}, jobs);
  cold.render_frame(6);
  const auto& c = cold.buffers().color;
  REQUIRE(c.size() == last[0].size());
  size_t differ = 0;
  for (size_t i = 0; i < c.size(); ++i)
    differ += glm::length(c[i] - last[0][i]) > 1e-3f * (glm::length(c[i]) + 1e-3f);
  CHECK(differ <= c.size() / 500);
}

TEST_CASE("camera keys interpolate, hold outside the keyed range and mark cuts") {
  cr::Scene scene;
  cr::SceneDescription d;
  cr::CameraKey a, b;
  a.frame = 10;
  a.position = {0, 1, 0};
  a.target = {0, 1, -1};
  b.frame = 20;
  b.position = {10, 1, 0};
  b.target = {10, 1, -1};
  b.cut = true;
  d.camera.keys = {a, b};
  CHECK(cr::make_frame_view(scene, d, 0, 16, 9).camera.position.x == doctest::Approx(0.0));
  CHECK(cr::make_frame_view(scene, d, 15, 16, 9).camera.position.x == doctest::Approx(5.0));
  CHECK(cr::make_frame_view(scene, d, 30, 16, 9).camera.position.x == doctest::Approx(10.0));
  CHECK(cr::make_frame_view(scene, d, 15, 16, 9).history_valid);
  CHECK_FALSE(cr::make_frame_view(scene, d, 20, 16, 9).history_valid);  // the cut
  CHECK_FALSE(cr::make_frame_view(scene, d, 0, 16, 9).history_valid);   // first frame
}

TEST_CASE("sun direction: azimuth from +Z towards +X, elevation above the horizon") {
  const glm::vec3 north = cr::sun_direction(0.0f, 0.0f), east = cr::sun_direction(90.0f, 0.0f);
  CHECK(north.z == doctest::Approx(1.0f));
  CHECK(east.x == doctest::Approx(1.0f));
  CHECK(cr::sun_direction(0.0f, 90.0f).y == doctest::Approx(1.0f));
  CHECK(cr::sun_direction(123.0f, -20.0f).y < 0.0f);
}

TEST_CASE("reference render: a box frame matches a re-render and differs from a moved camera") {
  // A small reference-render check with the image metrics that can fail: the
  // same view passes tight thresholds, a view 2 degrees off does not.
  Loaded l = load(kBox, 96, 64);
  auto display = [](const Loaded& scene, unsigned threads) {  // the resolved 8-bit frame as [0,1] values
    cr::JobSystem jobs(threads);
    cr::Renderer r(scene.scene, scene.description, scene.profile, {}, jobs);
    r.render_frame(0);
    cr::ImageRGBf img(r.buffers().width, r.buffers().height);
    for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = float(r.buffers().display[i]) / 255.0f;
    return img;
  };
  const cr::ImageRGBf ref = display(l, 2);
  cr::CompareThresholds tight;
  auto same = cr::compare_images(ref, display(l, 1), cr::ImageEncoding::Display, tight);
  CHECK(same.pass);
  // Turn the camera by 2 degrees: the check must notice.
  const cr::FrameView v = cr::make_frame_view(l.scene, cr::SceneDescription{}, 0, 96, 64);
  cr::CameraKey k;
  k.position = v.camera.position;
  k.target = v.camera.position + glm::dvec3(v.camera.forward) + glm::dvec3(v.camera.right) * 0.035;
  k.vfov_deg = glm::degrees(v.camera.vfov_rad);
  l.description.camera.keys = {k};
  l.description.camera.znear = v.camera.znear;
  auto moved = cr::compare_images(ref, display(l, 2), cr::ImageEncoding::Display, tight);
  CHECK_FALSE(moved.pass);
}

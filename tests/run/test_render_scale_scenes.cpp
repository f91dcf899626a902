// render_scale with the plugins: the default scene (sky, aerial
// perspective) and the fog valley rendered at half the size are
// deterministic, keep the output size, stay close to the full-scale frame,
// and the sky and fog work at the internal size.
#include <doctest/doctest.h>

#include <cstring>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/output/image_compare.h"

namespace {

const std::string kScenes = std::string(CR_BINARY_DIR) + "/scenes/";
const std::string kDesktop = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";

struct Rendered {
  cr::FrameBuffers buffers;
  nlohmann::json plugins;
};

Rendered render(const std::string& scene, int w, int h, float scale, unsigned threads, int frames = 1) {
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  cr::RunSetup setup = cr::load_run(kScenes + scene, kDesktop, registry, w, h, threads);
  setup.profile.render_scale = scale;
  cr::JobSystem jobs(threads);
  cr::Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
  renderer.keep_view_distances(true);
  Rendered out;
  for (int f = 0; f < frames; ++f) out.plugins = renderer.render_frame(f).plugins;
  out.buffers = renderer.buffers();
  return out;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

cr::ImageRGBf linear(const cr::FrameBuffers& b) {
  cr::ImageRGBf img(b.width, b.height);
  std::memcpy(img.rgb.data(), b.color.data(), b.color.size() * sizeof(glm::vec3));
  return img;
}

cr::ImageRGBf displayed(const cr::FrameBuffers& b) {
  cr::ImageRGBf img(b.width, b.height);
  for (size_t i = 0; i < b.display.size(); ++i) img.rgb[i] = float(b.display[i]) / 255.0f;
  return img;
}

}  // namespace

TEST_CASE("render_scale 0.5: the default scene at 160x90 is bit-identical at 1 and 2 threads and close to full scale") {
  const Rendered one = render("default.json", 160, 90, 0.5f, 1);
  const Rendered two = render("default.json", 160, 90, 0.5f, 2);
  REQUIRE(two.buffers.width == 160);
  REQUIRE(two.buffers.height == 90);
  CHECK(same_bytes(one.buffers.color, two.buffers.color));
  CHECK(same_bytes(one.buffers.depth, two.buffers.depth));
  CHECK(same_bytes(one.buffers.distance, two.buffers.distance));
  CHECK(same_bytes(one.buffers.display, two.buffers.display));

  const Rendered full = render("default.json", 160, 90, 1.0f, 2);
  const cr::CompareMetrics m =
      cr::compare_images(linear(full.buffers), linear(two.buffers), cr::ImageEncoding::Linear, {}).metrics;
  MESSAGE("relative luminance error at scale 0.5: mean " << m.rel_luminance_mean << ", p95 " << m.rel_luminance_p95);
  CHECK(m.rel_luminance_mean < 0.06);  // measured 0.041
}

TEST_CASE("render_scale 0.5: the fog's froxel grid covers the internal size") {
  // 320x180 at 0.5 renders at 160x90: the grid of a 160x90 frame.
  const Rendered scaled = render("fog_valley_sunrise.json", 320, 180, 0.5f, 2);
  const Rendered small = render("fog_valley_sunrise.json", 160, 90, 1.0f, 2);
  const Rendered large = render("fog_valley_sunrise.json", 320, 180, 1.0f, 2);
  REQUIRE(scaled.plugins.contains("fog"));
  CHECK(scaled.plugins["fog"]["froxels"] == small.plugins["fog"]["froxels"]);
  CHECK(scaled.plugins["fog"]["froxels"] != large.plugins["fog"]["froxels"]);
  // Compared as displayed: the low sun's disc is thousands of times brighter
  // than the sky beside it, so in linear values the few pixels it moves to
  // dominate a mean of relative errors.
  const cr::CompareMetrics m =
      cr::compare_images(displayed(large.buffers), displayed(scaled.buffers), cr::ImageEncoding::Display, {}).metrics;
  MESSAGE("fog valley, relative luminance error at scale 0.5 (displayed): mean " << m.rel_luminance_mean);
  CHECK(m.rel_luminance_mean < 0.05);  // measured 0.031
}

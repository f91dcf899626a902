// The profile's render_scale through the renderer (engine only): scale 1 is
// today's frame, a lower scale renders the scene at the internal size and
// hands out buffers of the output size; the memory estimate charges both.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/json_input.h"
#include "engine/render/frame_memory.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"

namespace {

const std::string kScene = std::string(CR_BINARY_DIR) + "/scenes/engine_only.json";
const std::string kDesktop = std::string(CR_SOURCE_DIR) + "/profiles/desktop.json";

cr::Profile desktop(const nlohmann::json& extra, int w, int h) {
  nlohmann::json doc = cr::load_json_file(kDesktop);
  doc.update(extra);
  cr::Profile p = cr::parse_profile(doc, kDesktop, {"atmosphere", "fog"});
  p.width = w;
  p.height = h;
  return p;
}

struct ScaledFrame {
  cr::FrameBuffers buffers;
  std::vector<std::string> passes;
  cr::FrameView view;
};

ScaledFrame render_scaled(const cr::Profile& profile, bool keep_distances) {
  const cr::SceneDescription description = cr::load_scene_description(kScene, {});
  const cr::Scene scene = cr::load_gltf(description.gltf_path);
  cr::JobSystem jobs(2);
  cr::Renderer r(scene, description, profile, {}, jobs);
  r.keep_view_distances(keep_distances);
  ScaledFrame f;
  for (const cr::PassTiming& p : r.render_frame(0).passes) f.passes.push_back(p.name);
  f.buffers = r.buffers();
  f.view = r.frame_view(0);
  return f;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool has_pass(const ScaledFrame& f, const std::string& name) {
  return std::find(f.passes.begin(), f.passes.end(), name) != f.passes.end();
}

}  // namespace

TEST_CASE("render_scale 1 renders exactly the bytes of a profile without the key, with no upscale pass") {
  const ScaledFrame plain = render_scaled(desktop(nlohmann::json::object(), 96, 54), true);
  const ScaledFrame one = render_scaled(desktop({{"render_scale", 1}}, 96, 54), true);
  CHECK_FALSE(has_pass(one, "upscale"));
  CHECK(one.passes == plain.passes);
  CHECK(same_bytes(one.buffers.color, plain.buffers.color));
  CHECK(same_bytes(one.buffers.depth, plain.buffers.depth));
  CHECK(same_bytes(one.buffers.distance, plain.buffers.distance));
  CHECK(same_bytes(one.buffers.display, plain.buffers.display));
  CHECK(one.buffers.fragments.size() == plain.buffers.fragments.size());
  CHECK(!plain.buffers.fragments.empty());  // the desktop profile's msaa4 edges were compared too
}

TEST_CASE("render_scale 0.5: the scene renders at the internal size into output-size buffers through an upscale pass") {
  const ScaledFrame f = render_scaled(desktop({{"render_scale", 0.5}}, 96, 54), false);
  CHECK(f.view.width == 48);
  CHECK(f.view.height == 27);
  CHECK(f.view.camera.aspect == doctest::Approx(96.0 / 54.0));  // the output's aspect ratio
  CHECK(f.buffers.width == 96);
  CHECK(f.buffers.height == 54);
  REQUIRE(f.buffers.color.size() == 96u * 54u);
  CHECK(f.buffers.display.size() == 96u * 54u * 3u);
  CHECK(f.buffers.fragments.empty());  // resolved at the internal size before the upscale
  // The upscale runs after the shading and before the display transform.
  const auto at = [&](const char* name) { return std::find(f.passes.begin(), f.passes.end(), name) - f.passes.begin(); };
  REQUIRE(has_pass(f, "upscale"));
  CHECK(at("shade") < at("upscale"));
  CHECK(at("upscale") < at("resolve"));
  // Depth upscaled (nearest), distances not computed when nothing reads them.
  CHECK(std::count(f.buffers.depth.begin(), f.buffers.depth.end(), 0.0f) < long(f.buffers.depth.size()));
  CHECK(std::all_of(f.buffers.distance.begin(), f.buffers.distance.end(), [](float d) { return std::isinf(d); }));
  CHECK_FALSE(has_pass(f, "view distance"));
  const ScaledFrame kept = render_scaled(desktop({{"render_scale", 0.5}}, 96, 54), true);
  CHECK(has_pass(kept, "view distance"));
  CHECK(std::any_of(kept.buffers.distance.begin(), kept.buffers.distance.end(), [](float d) { return std::isfinite(d); }));
  CHECK(same_bytes(kept.buffers.color, f.buffers.color));
}

TEST_CASE("render_scale: the memory estimate charges the internal buffers and the output's") {
  const auto charges = [](const cr::Profile& p) {
    cr::MemoryBudget memory(0);
    cr::estimate_frame_memory(p, memory);
    return memory;
  };
  const cr::MemoryBudget full = charges(desktop(nlohmann::json::object(), 1280, 720));
  const cr::MemoryBudget half = charges(desktop({{"render_scale", 0.5}}, 1280, 720));
  std::vector<std::string> what;
  for (const cr::MemoryBudget::Charge& c : half.charges()) what.push_back(c.what + " (" + c.field + ")");
  CAPTURE(what);
  const auto charged = [&](const std::string& s) {
    return std::any_of(what.begin(), what.end(), [&](const std::string& w) { return w == s; });
  };
  CHECK(charged("internal frame buffers of 640x360 (render_scale)"));
  CHECK(charged("output frame buffers of 1280x720 (resolution)"));
  CHECK(charged("4 samples per pixel at 640x360 (antialiasing)"));
  // Less than at full scale (the visibility and samples shrink), more than the output buffers alone.
  CHECK(half.total() < full.total());
  const cr::MemoryBudget quarter = charges(desktop({{"render_scale", 0.25}}, 1280, 720));
  CHECK(quarter.total() < half.total());
  CHECK(quarter.total() > size_t(1280) * 720 * (sizeof(glm::vec3) + 2 * sizeof(float) + 3));
}

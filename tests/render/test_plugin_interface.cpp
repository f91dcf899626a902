// The plugin interface, exercised by a trivial plugin that lives only here:
// passes, culling of unread work, light environment override, composite.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "engine/core/error.h"
#include "engine/render/frame_graph.h"
#include "engine/render/renderer.h"
#include "engine/render/view_distance.h"
#include "engine/scene/gltf_loader.h"

namespace {

// Paints the sky a constant colour, provides the light environment (no
// ambient term), and declares one pass nobody reads (which the frame graph
// must cull). `provides_light` false: it writes the light all the same, which
// the renderer must refuse.
class TintPlugin : public cr::Plugin {
 public:
  explicit TintPlugin(bool used, bool provides_light = true) : used_(used), provides_light_(provides_light) {}
  std::string name() const override { return "tint"; }
  bool configure(const cr::Scene&, const cr::SceneDescription&, const cr::Profile&) override { return used_; }
  bool provides_light_environment() const override { return provides_light_; }
  void add_passes(cr::FrameGraph& graph, const cr::FrameContext&, cr::EngineResources& engine) override {
    using Builder = cr::FrameGraph::Builder;
    using Resources = cr::FrameGraph::Resources;
    struct Data {
      cr::FrameGraphId<int> colour;
      cr::FrameGraphId<cr::LightEnvironment> light;
    };
    colour_ = graph.create("tint.colour", colour_value_);
    graph.add_pass<Data>("tint.prepare", [&](Builder& b, Data& d) { d.colour = colour_ = b.write(colour_); },
                         [this](const Resources& r, const Data& d) {
                           r.get_mutable(d.colour) = 1;
                           prepared++;
                         });
    graph.add_pass<Data>("tint.light", [&](Builder& b, Data& d) { d.light = engine.light = b.write(engine.light); },
                         [this](const Resources& r, const Data& d) {
                           cr::LightEnvironment& light = r.get_mutable(d.light);
                           light.ambient_sh = {};
                           light.ambient_sh[0] = glm::vec3(0.0f);
                           lit++;
                         });
    cr::FrameGraphId<int> unused = graph.create("tint.nobody_reads_this", unused_value_);
    graph.add_pass<Data>("tint.unused", [&](Builder& b, Data& d) { d.colour = b.write(unused); },
                         [this](const Resources&, const Data&) { unused_ran++; });
  }
  std::vector<cr::FrameGraphHandle> composite_reads() const override { return {colour_}; }
  bool has_composite() const override { return true; }
  void composite(cr::FrameBuffers& buffers, int x0, int y0, int x1, int y1) override {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t i = buffers.index(x, y);
        if (buffers.depth[i] == 0.0f && colour_value_ == 1) buffers.color[i] = glm::vec3(1.0f, 2.0f, 3.0f);
      }
  }
  void report_frame(nlohmann::json& frame) override { frame["prepared"] = prepared.load(); }

  std::atomic<int> prepared{0}, lit{0}, unused_ran{0};

 private:
  bool used_, provides_light_;
  int colour_value_ = 0, unused_value_ = 0;
  cr::FrameGraphId<int> colour_;
};

struct Fixture {
  cr::SceneDescription description = cr::load_scene_description(
      // One literal, not string + literal: GCC 12 -O3 warns falsely (-Warray-bounds) on the latter here in a unity build.
      CR_ASSIMP_GLTF_DIR "/BoxTextured-glTF/BoxTextured.gltf", {});
  cr::Profile profile;
  cr::Scene scene = cr::load_gltf(description.gltf_path);
  Fixture() {
    profile.width = 64;
    profile.height = 48;
  }
};

}  // namespace

TEST_CASE("a plugin adds passes, replaces the light, composites, and its unread pass is culled") {
  Fixture f;
  cr::JobSystem jobs(2);
  auto plugin = std::make_unique<TintPlugin>(true);
  TintPlugin* p = plugin.get();
  std::vector<std::unique_ptr<cr::Plugin>> plugins;
  plugins.push_back(std::move(plugin));
  cr::Renderer r(f.scene, f.description, f.profile, std::move(plugins), jobs);
  const cr::FrameRecord& rec = r.render_frame(0);
  CHECK(p->prepared == 1);
  CHECK(p->lit == 1);
  CHECK(p->unused_ran == 0);
  CHECK(std::find(rec.culled.begin(), rec.culled.end(), "tint.unused") != rec.culled.end());
  CHECK(rec.plugins["tint"]["prepared"] == 1);
  // Sky pixels carry the plugin's colour; the box's shaded pixels saw no ambient light.
  const cr::FrameBuffers& b = r.buffers();
  CHECK(b.color[0] == glm::vec3(1.0f, 2.0f, 3.0f));
  CHECK(r.light_environment().ambient_sh[0] == glm::vec3(0.0f));
}

TEST_CASE("a plugin the scene does not use adds no pass and costs nothing") {
  Fixture f;
  cr::JobSystem jobs(1);
  auto plugin = std::make_unique<TintPlugin>(false);
  TintPlugin* p = plugin.get();
  std::vector<std::unique_ptr<cr::Plugin>> plugins;
  plugins.push_back(std::move(plugin));
  cr::Renderer r(f.scene, f.description, f.profile, std::move(plugins), jobs);
  CHECK(r.plugin("tint") == nullptr);
  const cr::FrameRecord& rec = r.render_frame(0);
  (void)p;  // destroyed with the renderer's rejected list: never touched
  for (const auto& pass : rec.passes) CHECK(pass.name.rfind("tint.", 0) != 0);
  CHECK(rec.plugins.empty());
}

TEST_CASE("only the plugin that provides the light environment may write it, and a scene may use one provider") {
  Fixture f;
  cr::JobSystem jobs(1);
  {
    std::vector<std::unique_ptr<cr::Plugin>> plugins;
    plugins.push_back(std::make_unique<TintPlugin>(true, false));
    cr::Renderer r(f.scene, f.description, f.profile, std::move(plugins), jobs);
    CHECK_THROWS_WITH_AS(r.render_frame(0), "plugin 'tint' writes the light environment but does not provide it",
                         cr::Error);
  }
  std::vector<std::unique_ptr<cr::Plugin>> plugins;
  plugins.push_back(std::make_unique<TintPlugin>(true));
  plugins.push_back(std::make_unique<TintPlugin>(true));
  CHECK_THROWS_WITH_AS(cr::Renderer(f.scene, f.description, f.profile, std::move(plugins), jobs),
                       doctest::Contains("both provide the light environment"), cr::InputError);
}

namespace {

// Claims the pixels where nothing was drawn: paints them on frame 0 only, so
// a later frame shows whether anything else wrote them.
class BackgroundPlugin : public cr::Plugin {
 public:
  std::string name() const override { return "background"; }
  bool configure(const cr::Scene&, const cr::SceneDescription&, const cr::Profile&) override { return true; }
  void add_passes(cr::FrameGraph&, const cr::FrameContext& ctx, cr::EngineResources&) override {
    frame_ = ctx.view.frame;
  }
  bool has_composite() const override { return true; }
  bool composites_background() const override { return true; }
  void composite(cr::FrameBuffers& buffers, int x0, int y0, int x1, int y1) override {
    if (frame_ != 0) return;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (buffers.depth[buffers.index(x, y)] == 0.0f) buffers.color[buffers.index(x, y)] = glm::vec3(4.0f, 5.0f, 6.0f);
  }

 private:
  int frame_ = 0;
};

bool culled(const cr::FrameRecord& rec, const std::string& pass) {
  return std::find(rec.culled.begin(), rec.culled.end(), pass) != rec.culled.end();
}

}  // namespace

TEST_CASE("the shade pass leaves pixels where nothing was drawn to a plugin that composites them") {
  Fixture f;
  cr::JobSystem jobs(2);
  std::vector<std::unique_ptr<cr::Plugin>> plugins;
  plugins.push_back(std::make_unique<BackgroundPlugin>());
  cr::Renderer r(f.scene, f.description, f.profile, std::move(plugins), jobs);
  r.render_frame(0);
  r.render_frame(1);  // the plugin paints nothing now: frame 0's colour must remain
  const cr::FrameBuffers& b = r.buffers();
  CHECK(b.depth[0] == 0.0f);
  CHECK(b.color[0] == glm::vec3(4.0f, 5.0f, 6.0f));
  // Without such a plugin they take the flat background (the ambient radiance).
  cr::Renderer plain(f.scene, f.description, f.profile, {}, jobs);
  plain.render_frame(0);
  CHECK(plain.buffers().color[0] == f.description.ambient);
}

TEST_CASE("view distances are computed for the frames that read them, or when kept") {
  Fixture f;
  cr::JobSystem jobs(2);
  cr::Renderer plain(f.scene, f.description, f.profile, {}, jobs);
  CHECK(culled(plain.render_frame(0), "view distance"));
  const cr::FrameBuffers& b = plain.buffers();
  CHECK(std::all_of(b.distance.begin(), b.distance.end(), [](float d) { return std::isinf(d); }));

  plain.keep_view_distances(true);
  CHECK_FALSE(culled(plain.render_frame(1), "view distance"));
  const size_t centre = b.index(b.width / 2, b.height / 2);
  REQUIRE(b.depth[centre] > 0.0f);  // the box
  const cr::Camera cam = plain.frame_view(1).camera;
  CHECK(b.distance[centre] ==
        cr::view_distance(cam, b.width, b.height, float(b.width / 2) + 0.5f, float(b.height / 2) + 0.5f,
                          b.depth[centre]));

  // A composite reads them: computed without being kept.
  std::vector<std::unique_ptr<cr::Plugin>> plugins;
  plugins.push_back(std::make_unique<TintPlugin>(true));
  cr::Renderer tinted(f.scene, f.description, f.profile, std::move(plugins), jobs);
  CHECK_FALSE(culled(tinted.render_frame(0), "view distance"));
  CHECK(std::isfinite(tinted.buffers().distance[centre]));
}

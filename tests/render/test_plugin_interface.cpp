// The plugin interface, exercised by a trivial plugin that lives only here:
// passes, culling of unread work, light environment override, composite.
#include <doctest/doctest.h>

#include <atomic>

#include "engine/render/frame_graph.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"

namespace {

// Paints the sky a constant colour, sets the ambient term, and declares one
// pass nobody reads (which the frame graph must cull).
class TintPlugin : public cr::Plugin {
 public:
  explicit TintPlugin(bool used) : used_(used) {}
  std::string name() const override { return "tint"; }
  bool configure(const cr::Scene&, const cr::SceneDescription&, const cr::Profile&) override { return used_; }
  void add_passes(cr::FrameGraph& graph, cr::FrameContext& ctx) override {
    graph.add_pass("tint.prepare", [](cr::FrameGraph::Builder& b) { b.write("tint.colour"); },
                   [this] { prepared++; });
    graph.add_pass("tint.light", [](cr::FrameGraph::Builder& b) { b.read("light_environment").write("light_environment"); },
                   [this, &ctx] {
                     ctx.light.ambient_sh = {};
                     ctx.light.ambient_sh[0] = glm::vec3(0.0f);
                     lit++;
                   });
    graph.add_pass("tint.unused", [](cr::FrameGraph::Builder& b) { b.write("tint.nobody_reads_this"); },
                   [this] { unused_ran++; });
  }
  std::vector<std::string> composite_reads() const override { return {"tint.colour"}; }
  bool has_composite() const override { return true; }
  void composite(const cr::FrameContext& ctx, int x0, int y0, int x1, int y1) override {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t i = ctx.buffers.index(x, y);
        if (ctx.buffers.depth[i] == 0.0f) ctx.buffers.color[i] = glm::vec3(1.0f, 2.0f, 3.0f);
      }
  }
  void report_frame(nlohmann::json& frame) override { frame["prepared"] = prepared.load(); }

  std::atomic<int> prepared{0}, lit{0}, unused_ran{0};

 private:
  bool used_;
};

struct Fixture {
  cr::SceneDescription description = cr::load_scene_description(
      std::string(CR_ASSIMP_GLTF_DIR) + "/BoxTextured-glTF/BoxTextured.gltf", {});
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

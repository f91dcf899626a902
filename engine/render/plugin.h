#pragma once
// The plugin interface. A plugin (the atmosphere, the fog) adds passes and
// resources to the frame graph, reads the engine's resources through the
// handles it is given, may provide the light environment (the sun and
// ambient terms shading uses), and composites per pixel after shading. The
// engine knows no plugin by name; the CLI registers them in a PluginRegistry.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/memory_budget.h"
#include "engine/core/profile.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/frame_graph.h"
#include "engine/render/module_plan.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"

namespace cr {

// What one frame is: camera now and before, sun, image size.
struct FrameView {
  int frame = 0;
  int width = 0;
  int height = 0;
  Camera camera;
  Camera prev_camera;        // equals camera on the first frame and after a cut
  bool history_valid = false;  // false on the first frame and on camera cuts
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};  // unit, towards the sun
  glm::vec3 sun_illuminance{0.0f};            // RGB lux, unattenuated
};

// What a frame is made of, for declaring passes: values, no buffers (those
// are resources of the graph).
struct FrameContext {
  const Scene& scene;
  const SceneDescription& description;
  const Profile& profile;
  FrameView view;
};

// The engine's resources in this frame's graph, at the versions a plugin's
// passes read (a pass that writes one stores the version it returns here).
struct EngineResources {
  // Sun and ambient terms for shading: written by the engine's "light" pass,
  // then by the light-environment provider's passes, if a plugin provides it.
  FrameGraphId<LightEnvironment> light;
  // The sun's shadow map (size 0 without a shadow pass), and last frame's map
  // where this frame's is a new render (the sun or the texel-snapped
  // projection moved), else size 0; both written by the "shadow" pass.
  FrameGraphId<ShadowMap> shadow;
  FrameGraphId<ShadowMap> previous_shadow;
  // FrameBuffers::depth and the edge fragments' positions and distances,
  // written by the "geometry" pass.
  FrameGraphId<FrameBuffers> depth;
  // FrameBuffers::distance (metres along each pixel's view ray), written from
  // depth by the "view distance" pass, which a frame whose passes do not read
  // it culls.
  FrameGraphId<FrameBuffers> distance;
};

class Plugin {
 public:
  virtual ~Plugin() = default;
  // The plugin's name, also its section name in profiles and scene files.
  virtual std::string name() const = 0;
  // Validates the plugin's profile and scene sections (InputError naming the
  // file and field). Returns false when the scene does not use the plugin:
  // it then adds no passes and costs nothing.
  virtual bool configure(const Scene& scene, const SceneDescription& description,
                         const Profile& profile) = 0;
  // Charges to `memory` what configure() and the frames would allocate for
  // this description and profile (LUTs, grids), before anything is
  // allocated; nothing when the description does not use the plugin.
  // Throws InputError as configure() does.
  virtual void estimate_memory(const SceneDescription& description, const Profile& profile,
                               MemoryBudget& memory) const {
    (void)description; (void)profile; (void)memory;
  }
  // Whether this plugin's passes write the light environment (the sky does).
  // The renderer declares the provider's passes before any other plugin's,
  // so those and the shade pass read its light; a scene may use one provider.
  virtual bool provides_light_environment() const { return false; }
  // Declares this frame's passes; only the provider may write engine.light.
  // The graph culls passes nobody reads.
  virtual void add_passes(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) = 0;
  // This frame's resources the per-pixel composite reads (become reads of
  // the composite pass).
  virtual std::vector<FrameGraphHandle> composite_reads() const { return {}; }
  // Plugins composite in increasing order (sky and aerial perspective before fog).
  virtual int composite_order() const { return 0; }
  // Per-pixel composite of the rectangle [x0,x1) x [y0,y1) of buffers.color
  // (depth and distance valid); called from parallel tile jobs, so it writes
  // only inside its rectangle.
  virtual void composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) {
    (void)buffers; (void)x0; (void)y0; (void)x1; (void)y1;
  }
  virtual bool has_composite() const { return false; }
  // Whether the composite writes every pixel where nothing was drawn (depth
  // 0) without reading its colour (a sky does): the shade pass then leaves
  // those pixels to it instead of filling them with the flat background.
  virtual bool composites_background() const { return false; }
  // The same composite for edge-pixel fragments (a range of buffers.fragments):
  // each at its own screen position and distance, in place; called from
  // parallel jobs on disjoint ranges. A plugin with a composite must give
  // fragments what it gives pixels.
  virtual void composite_fragments(const FrameBuffers& buffers, std::span<EdgeFragment> fragments) {
    (void)buffers; (void)fragments;
  }
  // What the `auto` planner may choose for this plugin (engine/planning/
  // auto_plan.h): by default the table's options as they are. A plugin
  // overrides it to skip what the scene does not use (used = false) and to
  // add the settings the scene decides. Throws InputError as configure() does.
  virtual ModulePlan plan(const PlanContext& ctx) const {
    ModulePlan m;
    m.module = name();
    m.options = parse_plan_options(ctx.table_options, ctx.table_path, name());
    return m;
  }
  // How many frames a render must run before a frame so that what this
  // plugin carries from frame to frame (a temporal history, amortised LUT
  // rebuilds) depends on where rendering started by at most `tolerance` of
  // the frame's values: the warm-up of a render that starts mid-path (a
  // shard). 0: the plugin keeps no such state.
  virtual int warmup_frames(double tolerance) const {
    (void)tolerance;
    return 0;
  }
  // Adds the plugin's per-frame figures (e.g. LUT bake times) to the report.
  virtual void report_frame(nlohmann::json& frame) { (void)frame; }
};

}  // namespace cr

#pragma once
// The plugin interface. A plugin (the atmosphere, the fog) adds passes and
// resources to the frame graph, may replace the sun/ambient terms through the
// "light_environment" resource, and composites per pixel after shading. The
// engine knows no plugin by name; the CLI registers them in a PluginRegistry.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/job_system.h"
#include "engine/core/memory_budget.h"
#include "engine/core/profile.h"
#include "engine/render/frame_buffers.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"

namespace cr {

class FrameGraph;

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

// Everything a pass may touch during a frame. Resources produced by engine
// passes: "light_environment" (light), "shadow_map" (shadow), "visibility"
// and "depth" (geometry: buffers.depth and buffers.distance are valid once a
// pass that reads "depth" runs), "hdr_color" (shade: buffers.color), "frame"
// (resolve: buffers.display).
struct FrameContext {
  const Scene& scene;
  const SceneDescription& description;
  const Profile& profile;
  JobSystem& jobs;
  FrameView view;
  FrameBuffers& buffers;
  LightEnvironment& light;
  const ShadowMap& shadow;  // size 0 when there is no shadow pass
  // Last frame's map where this frame's is a new render (the sun or the
  // texel-snapped projection moved), else size 0; valid from the shadow pass on.
  const ShadowMap& previous_shadow;
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
  // Declares this frame's passes. The graph culls those nobody reads.
  virtual void add_passes(FrameGraph& graph, FrameContext& ctx) = 0;
  // Resources the per-pixel composite reads (become reads of the composite pass).
  virtual std::vector<std::string> composite_reads() const { return {}; }
  // Plugins composite in increasing order (sky and aerial perspective before fog).
  virtual int composite_order() const { return 0; }
  // Per-pixel composite of the rectangle [x0,x1) x [y0,y1) of ctx.buffers.color;
  // called from parallel tile jobs, so it writes only inside its rectangle.
  virtual void composite(const FrameContext& ctx, int x0, int y0, int x1, int y1) {
    (void)ctx; (void)x0; (void)y0; (void)x1; (void)y1;
  }
  virtual bool has_composite() const { return false; }
  // The same composite for edge-pixel fragments (FrameBuffers::fragments):
  // each at its own screen position and distance, in place; called from
  // parallel jobs on disjoint ranges. A plugin with a composite must give
  // fragments what it gives pixels.
  virtual void composite_fragments(const FrameContext& ctx, std::span<EdgeFragment> fragments) {
    (void)ctx; (void)fragments;
  }
  // Adds the plugin's per-frame figures (e.g. LUT bake times) to the report.
  virtual void report_frame(nlohmann::json& frame) { (void)frame; }
};

}  // namespace cr

#pragma once
// Renders frames of a loaded scene: builds the frame graph each frame from
// what the scene and plugins need (the engine's passes, engine/render/passes/,
// and the plugins'), runs it on the job system and keeps per-frame timing
// records.
// Frames must be rendered in increasing order (plugins keep temporal state).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/job_system.h"
#include "engine/core/profile.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/frame_graph.h"
#include "engine/render/plugin.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"

namespace cr {

class DisplayTransform;
class Hdr16Display;
struct ShadowPassState;
class SurfaceLookup;
class Upscaler;
struct Visibility;

// Timing of one rendered frame and its rasterizer counts.
struct FrameRecord : FrameTiming {
  nlohmann::json raster = nlohmann::json::object();  // triangles, pixels, fragments, draws
};

class Renderer {
 public:
  // Plugins are configured here; those the scene does not use are dropped.
  Renderer(const Scene& scene, const SceneDescription& description, const Profile& profile,
           std::vector<std::unique_ptr<Plugin>> plugins, JobSystem& jobs);
  ~Renderer();

  // The camera and sun of a frame (pure function of the scene description),
  // at the internal size the scene renders at (Profile::render_width()).
  FrameView frame_view(int frame) const;
  // Renders one frame into buffers(); returns its timing record.
  const FrameRecord& render_frame(int frame);
  // Scene playback: `pose(frame)` re-poses the scene (the one this renderer
  // draws) before each frame. The scene then changes between frames, so
  // nothing drawn from it is reused across frames (the shadow map).
  void play_animation(std::function<void(int frame)> pose) { pose_ = std::move(pose); }

  // buffers().distance is computed only for frames whose passes read it (sky,
  // fog) unless kept; otherwise it holds +inf.
  void keep_view_distances(bool keep) { keep_view_distances_ = keep; }
  // The frame at the output size. With the profile's render_scale below 1
  // the scene renders into internal buffers (frame_view()'s size) and these
  // hold the upscale: colour filtered, depth and distance the nearest
  // internal pixel's, no edge fragments.
  const FrameBuffers& buffers() const { return buffers_; }
  // The draw (index into Scene::draws) the last frame's pixels see at their
  // first sample, at the internal size; -1 where nothing was drawn (for
  // tools that find edges).
  std::vector<int32_t> pixel_draws() const;
  const ShadowMap& shadow_map() const { return shadow_; }
  // Last frame's map where this frame's is a new render, else size 0.
  const ShadowMap& previous_shadow_map() const { return previous_shadow_; }
  const LightEnvironment& light_environment() const { return light_; }
  Plugin* plugin(const std::string& name) const;  // nullptr when absent or unused by the scene
  const std::vector<std::unique_ptr<Plugin>>& plugins() const { return plugins_; }
  // Frames to render before a frame so that it depends on where rendering
  // started by at most `tolerance` (Plugin::warmup_frames over the scene's
  // plugins). The engine's own carried state, the scrolled shadow map,
  // needs none: a cold start renders it whole, which a scrolled map equals
  // to rounding (shadow_scroll.h).
  int warmup_frames(double tolerance) const;

 private:
  const Scene& scene_;
  const SceneDescription& description_;
  const Profile& profile_;
  JobSystem& jobs_;
  std::vector<std::unique_ptr<Plugin>> plugins_;
  Plugin* light_provider_ = nullptr;  // the plugin providing the light environment, if any
  FrameBuffers buffers_;                     // at the output size
  FrameBuffers internal_;                    // at the internal size, when it differs
  std::unique_ptr<Upscaler> upscaler_;       // from internal_ to buffers_; null at the output size
  ShadowMap shadow_, previous_shadow_;
  LightEnvironment light_;
  std::unique_ptr<Visibility> visibility_;         // the geometry pass's rasterizer and draws
  std::unique_ptr<ShadowPassState> shadow_state_;  // the shadow pass's rasterizer and casters
  std::unique_ptr<SurfaceLookup> surfaces_;        // the shading passes' triangle lookup (materials fixed)
  bool keep_view_distances_ = false;               // computed even when no pass reads them
  bool has_blended_draws_ = false;                 // the scene has alpha-BLEND draws: a transparent pass
  std::unique_ptr<DisplayTransform> display_;  // built once per exposure
  std::unique_ptr<Hdr16Display> fixed_display_;  // the same as a table of hdr16 codes (fixed-point resolve)
  FrameRecord record_;
  int last_frame_ = -1;
  std::function<void(int)> pose_;  // empty: a still scene
  uint64_t pixels_shaded_ = 0;  // by the last frame's shade pass
};

}  // namespace cr

#include "engine/render/renderer.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/render/display_transform.h"
#include "engine/render/frame_view.h"
#include "engine/render/passes/draw_materials.h"
#include "engine/render/passes/engine_passes.h"
#include "engine/render/passes/surface_lookup.h"
#include "engine/render/upscale.h"
#include "engine/shading/tonemap.h"

namespace cr {

Renderer::Renderer(const Scene& scene, const SceneDescription& description, const Profile& profile,
                   std::vector<std::unique_ptr<Plugin>> plugins, JobSystem& jobs)
    : scene_(scene), description_(description), profile_(profile), jobs_(jobs),
      visibility_(std::make_unique<Visibility>()), shadow_state_(std::make_unique<ShadowPassState>()),
      surfaces_(std::make_unique<SurfaceLookup>(scene, profile.half_attributes)) {
  if (description.camera.gltf_camera && *description.camera.gltf_camera >= int(scene.cameras.size()))
    throw InputError(description.path, "camera.gltf_camera is " + std::to_string(*description.camera.gltf_camera) +
                                           " but '" + scene.source + "' has " + std::to_string(scene.cameras.size()) +
                                           " perspective camera(s)");
  for (auto& p : plugins)
    if (p->configure(scene, description, profile)) plugins_.push_back(std::move(p));
  std::stable_sort(plugins_.begin(), plugins_.end(),
                   [](const auto& a, const auto& b) { return a->composite_order() < b->composite_order(); });
  for (const auto& p : plugins_)
    if (p->provides_light_environment()) {
      if (light_provider_)
        throw InputError(description.path, "plugins '" + light_provider_->name() + "' and '" + p->name() +
                                               "' both provide the light environment; a scene may use one");
      light_provider_ = p.get();
    }
  for (const Draw& d : scene.draws)
    if (material_of(scene, scene.primitive(d)).alpha_mode == AlphaMode::Blend) has_blended_draws_ = true;
  buffers_.resize(profile.width, profile.height);
  if (profile.scaled()) {
    internal_.resize(profile.render_width(), profile.render_height(), false);
    upscaler_ = std::make_unique<Upscaler>(internal_.width, internal_.height, buffers_.width, buffers_.height);
  }
}

Renderer::~Renderer() = default;

std::vector<int32_t> Renderer::pixel_draws() const {
  const VisibilityBuffer& v = visibility_->raster.visibility();
  std::vector<int32_t> draws(v.triangle.size(), -1);
  for (size_t i = 0; i < draws.size(); ++i)
    if (v.triangle[i] != kNoTriangle) draws[i] = int32_t(visibility_->raster.ref(v.triangle[i]).draw_index);
  return draws;
}

FrameView Renderer::frame_view(int frame) const {
  FrameView view = make_frame_view(scene_, description_, frame, profile_.width, profile_.height);
  // The camera keeps the output's aspect ratio: the upscale stretches each
  // axis back to the output, so rounding the internal size distorts nothing.
  view.width = profile_.render_width();
  view.height = profile_.render_height();
  return view;
}

int Renderer::warmup_frames(double tolerance) const {
  int frames = 0;
  for (const auto& p : plugins_) frames = std::max(frames, p->warmup_frames(tolerance));
  return frames;
}

Plugin* Renderer::plugin(const std::string& name) const {
  for (const auto& p : plugins_)
    if (p->name() == name) return p.get();
  return nullptr;
}

const FrameRecord& Renderer::render_frame(int frame) {
  if (frame <= last_frame_) throw Error("renderer: frames must be rendered in increasing order");
  PassTiming pose{"pose", jobs_.now_us(), 0.0};
  if (pose_) pose_(frame);
  pose.end_us = jobs_.now_us();
  FrameView view = frame_view(frame);
  if (frame != last_frame_ + 1) {  // skipped frames: temporal history is not valid
    view.history_valid = false;
    view.prev_camera = view.camera;
  }
  last_frame_ = frame;

  const FrameContext ctx{scene_, description_, profile_, view};
  const bool shadows = profile_.shadow_map_size > 0 && sun_is_up(view);
  if (!shadows) shadow_ = previous_shadow_ = ShadowMap{};  // no map this frame

  FrameGraph graph;
  EngineResources engine;
  engine.light = graph.create("light_environment", light_);
  engine.shadow = graph.import("shadow_map", shadow_);
  engine.previous_shadow = graph.import("previous_shadow_map", previous_shadow_);
  FrameBuffers& scene_buffers = upscaler_ ? internal_ : buffers_;  // what the scene renders into
  engine.depth = graph.create("depth", scene_buffers);
  engine.distance = graph.create("distance", scene_buffers);
  EngineTargets targets;
  targets.visibility = graph.create("visibility", *visibility_);
  targets.color = graph.create("hdr_color", scene_buffers);
  targets.display = graph.create("frame", buffers_);

  add_light_pass(graph, ctx, engine);
  if (shadows) add_shadow_pass(graph, ctx, bool(pose_), *shadow_state_, engine);
  add_geometry_pass(graph, ctx, engine, targets);
  add_view_distance_pass(graph, ctx, engine);
  // The light-environment provider declares its passes first: every other
  // plugin's passes and the shade pass read the light it writes.
  if (light_provider_) light_provider_->add_passes(graph, ctx, engine);
  for (auto& p : plugins_) {
    if (p.get() == light_provider_) continue;
    const FrameGraphHandle light = engine.light;
    p->add_passes(graph, ctx, engine);
    if (engine.light.version() != light.version())
      throw Error("plugin '" + p->name() + "' writes the light environment but does not provide it");
  }
  std::vector<Plugin*> compositors;
  for (auto& p : plugins_)
    if (p->has_composite()) compositors.push_back(p.get());
  const bool background_composited =
      std::any_of(compositors.begin(), compositors.end(), [](const Plugin* p) { return p->composites_background(); });
  add_shade_pass(graph, ctx, *surfaces_, engine, targets, !background_composited, pixels_shaded_);
  if (has_blended_draws_) add_transparent_pass(graph, ctx, *surfaces_, engine, targets);
  if (!compositors.empty()) add_composite_pass(graph, compositors, engine, targets);
  if (upscaler_)
    add_upscale_pass(graph, *upscaler_, engine, targets, graph.create("upscaled", buffers_), keep_view_distances_,
                     exposure_scale(ctx.description.exposure_ev100));
  add_resolve_pass(graph, ctx, display_, fixed_display_, targets);
  graph.mark_output(targets.display);
  if (keep_view_distances_) graph.mark_output(engine.distance);

  graph.compile();
  jobs_.take_records();
  record_ = FrameRecord{};
  record_.frame = frame;
  record_.begin_us = jobs_.now_us();
  graph.execute(jobs_);
  record_.frame_ms = (jobs_.now_us() - record_.begin_us) * 1e-3;
  record_.passes = graph.timings();
  if (pose_) {  // playback's posing is part of the frame's cost
    record_.frame_ms += pose.ms();
    record_.passes.insert(record_.passes.begin(), pose);
  }
  record_.culled = graph.culled_pass_names();
  record_.jobs = jobs_.take_records();
  const Visibility& vis = *visibility_;
  const RasterStats& st = vis.stats;
  uint64_t mixed_pixels = 0;  // pixels whose samples see more than one triangle
  for (const MixedSamples& m : vis.raster.visibility().mixed) mixed_pixels += m.pixels.size();
  record_.raster = {{"triangles_in", st.triangles_in},       {"triangles_culled", st.triangles_culled},
                    {"triangles_clipped", st.triangles_clipped}, {"triangles_visible", st.triangles_visible},
                    {"tile_triangle_pairs", st.tile_triangle_pairs}, {"pixels_covered", st.pixels_covered},
                    {"pixels_shaded", pixels_shaded_},
                    {"msaa_mixed_pixels", mixed_pixels}, {"edge_fragments", scene_buffers.fragments.size()},
                    {"draws_in_view", vis.opaque.size() + vis.blended.size()},
                    {"shadow_casters", shadow_state_->casters.size()}, {"shadow_map_reused", shadow_state_->reused},
                    {"shadow_map_scrolled", shadow_state_->scrolled}};
  for (auto& p : plugins_) p->report_frame(record_.plugins[p->name()]);
  return record_;
}

}  // namespace cr

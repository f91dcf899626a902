// "shadow": the sun's shadow map, fitted to the view and texel-snapped.
#include "engine/render/passes/draw_culling.h"
#include "engine/render/passes/draw_materials.h"
#include "engine/render/passes/engine_passes.h"
#include "engine/shading/shadow_map.h"

namespace cr {

void add_shadow_pass(FrameGraph& graph, const FrameContext& ctx, bool scene_moves, ShadowPassState& state,
                     EngineResources& engine) {
  struct Data {
    FrameGraphId<ShadowMap> shadow, previous;
  };
  graph.add_pass<Data>("shadow", [&](FrameGraph::Builder& b, Data& d) {
    d.shadow = engine.shadow = b.write(engine.shadow);
    d.previous = engine.previous_shadow = b.write(engine.previous_shadow);
  }, [ctx, scene_moves, &state](const FrameGraph::Resources& r, const Data& d) {
    const Scene& scene = ctx.scene;
    const Profile& profile = ctx.profile;
    ShadowMap& shadow = r.get_mutable(d.shadow);
    ShadowMap& previous = r.get_mutable(d.previous);
    ShadowMap fit = fit_shadow_projection(ctx.view.camera, ctx.view.sun_direction, profile.shadow_distance,
                                          profile.shadow_map_size, profile.shadow_pcf_radius, scene.bounds_min,
                                          scene.bounds_max);
    // A still scene: when the texel-snapped projection has not moved, last
    // frame's map is exactly what a new render would produce.
    const bool unchanged = !scene_moves && fit.size == shadow.size && fit.light_view_proj == shadow.light_view_proj &&
                           fit.origin == shadow.origin && fit.direction_to_sun == shadow.direction_to_sun;
    if (unchanged) {
      previous.size = 0;  // nothing to compare against (its memory is kept for the next render)
      state.reused = true;
      return;
    }
    // Last frame's map becomes the previous one (temporal plugins compare
    // against it when the sun moves); the new map renders into the memory
    // of the one before (the render writes every texel).
    fit.depth.swap(previous.depth);
    previous = std::move(shadow);
    shadow = std::move(fit);
    state.reused = false;
    state.casters.clear();
    for (uint32_t i = 0; i < scene.draws.size(); ++i) {
      const Draw& dr = scene.draws[i];
      const Material& m = material_of(scene, scene.primitive(dr));
      if (m.alpha_mode == AlphaMode::Blend) continue;  // translucent surfaces cast no shadow
      if (!aabb_in_ortho(shadow.light_view_proj, shadow.origin, dr.world_bounds_min, dr.world_bounds_max)) continue;
      state.casters.push_back({&scene.primitive(dr), model_to_clip(shadow.light_view_proj, shadow.origin, dr.world),
                               true, dr.mirrored, m.alpha_mode == AlphaMode::Mask, i});
    }
    state.raster.render_depth(r.jobs(), shadow.size, profile.tile_size, state.casters, shadow.depth,
                              alpha_coverage(scene, state.raster));
  });
}

}  // namespace cr

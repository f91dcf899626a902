// "shadow": the sun's shadow map, fitted to the view and texel-snapped;
// kept while nothing moves, scrolled while only the camera does.
#include <algorithm>

#include "engine/render/passes/draw_culling.h"
#include "engine/render/passes/draw_materials.h"
#include "engine/render/passes/engine_passes.h"
#include "engine/shading/shadow_map.h"
#include "engine/shading/shadow_scroll.h"

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
    const ShadowFit fit = fit_shadow_view(ctx.view.camera, ctx.view.sun_direction, profile.shadow_distance,
                                          profile.shadow_map_size, scene.bounds_min, scene.bounds_max);
    // A camera path gets a map that can scroll: a depth margin of the view
    // sphere's radius lets the view move that far along the sun's axis
    // before the map must render whole again.
    const double margin = ctx.description.camera.keys.size() > 1 ? -fit.need_min : 0.0;
    // Moving geometry invalidates every texel: no map to keep or scroll.
    ShadowUpdate update = plan_shadow_update(scene_moves ? ShadowMap{} : shadow, fit, profile.shadow_pcf_radius, margin);
    state.scrolled = update.scroll && (update.dx != 0 || update.dy != 0);
    state.reused = update.scroll && !state.scrolled;
    if (update.scroll) {
      previous.size = 0;  // no sun move to compare against (its memory is kept)
      if (state.reused) return;  // last frame's map is this frame's
      scroll_depth(r.jobs(), shadow.depth, shadow.size, update.dx, update.dy, previous.depth);
      update.map.depth.swap(previous.depth);
      previous.depth.swap(shadow.depth);
    } else {
      // Last frame's map becomes the previous one (temporal plugins compare
      // against it when the sun moves); the new map renders into the memory
      // of the one before (the render writes every texel).
      update.map.depth.swap(previous.depth);
      previous = std::move(shadow);
    }
    shadow = std::move(update.map);
    // A scrolled map renders only the tiles coming into view, so only the
    // casters that reach them matter.
    const std::vector<PixelRect> regions = state.scrolled
                                               ? exposed_tiles(shadow.size, profile.tile_size, update.dx, update.dy)
                                               : std::vector<PixelRect>{};
    std::vector<glm::mat4> region_clips;
    for (const PixelRect& rect : regions) region_clips.push_back(region_projection(shadow, rect));
    state.casters.clear();
    for (uint32_t i = 0; i < scene.draws.size(); ++i) {
      const Draw& dr = scene.draws[i];
      const Material& m = material_of(scene, scene.primitive(dr));
      if (m.alpha_mode == AlphaMode::Blend) continue;  // translucent surfaces cast no shadow
      if (!aabb_in_ortho(shadow.light_view_proj, shadow.origin, dr.world_bounds_min, dr.world_bounds_max)) continue;
      if (!region_clips.empty() && std::none_of(region_clips.begin(), region_clips.end(), [&](const glm::mat4& clip) {
            return aabb_in_ortho(clip, shadow.origin, dr.world_bounds_min, dr.world_bounds_max);
          }))
        continue;
      state.casters.push_back({&scene.primitive(dr), model_to_clip(shadow.light_view_proj, shadow.origin, dr.world),
                               true, dr.mirrored, m.alpha_mode == AlphaMode::Mask, i});
    }
    state.raster.render_depth(r.jobs(), shadow.size, profile.tile_size, state.casters, shadow.depth,
                              alpha_coverage(scene, state.raster), regions);
  });
}

}  // namespace cr

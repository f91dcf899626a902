#pragma once
// The engine's own passes, one file each: light, shadow, geometry, shade,
// transparent, composite, upscale, resolve. Each adds itself to the frame graph,
// reads and writes the engine's resources through their handles, and keeps
// what it reuses across frames in the state struct it is given.
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/profile.h"
#include "engine/raster/tiled_rasterizer.h"
#include "engine/render/edge_fragments.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/frame_graph.h"
#include "engine/render/plugin.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_description.h"

namespace cr {

class DisplayTransform;
class Hdr16Display;
class SurfaceLookup;
class Upscaler;

// The camera's visibility: the rasterizer (visibility buffer, bins), the
// frame's draws in view (the blended ones back to front), its counts and,
// with multisampling, the per-pixel ids and the fragment lists per tile row.
struct Visibility {
  TiledRasterizer raster;
  std::vector<RasterDraw> opaque, blended;
  RasterStats stats;
  std::vector<uint32_t> pixel_ids;  // edge_pixel_id at edge pixels
  FragmentRows fragment_rows;
};

// The sun's depth rasterizer, its casters and whether the last frame's map
// was kept (the projection did not move).
struct ShadowPassState {
  TiledRasterizer raster;
  std::vector<RasterDraw> casters;
  bool reused = false;    // this frame's map is last frame's
  bool scrolled = false;  // last frame's, moved: only the texels that came into view rendered
};

// The engine's resources that plugins do not see.
struct EngineTargets {
  FrameGraphId<Visibility> visibility;
  // FrameBuffers::color and the edge fragments' colours: the internal
  // buffers', after an upscale the output buffers'.
  FrameGraphId<FrameBuffers> color;
  FrameGraphId<FrameBuffers> display;  // FrameBuffers::display
};

// The sun lights the scene (above the horizon, with some illuminance).
inline bool sun_is_up(const FrameView& view) {
  return view.sun_direction.y > 0.0f && glm::length(view.sun_illuminance) > 0.0f;
}

// "light": the scene file's sun and ambient terms (a plugin may replace them).
void add_light_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine);
// "shadow": the sun's shadow map, kept when its texel-snapped projection did
// not move in a still scene (`scene_moves` false).
void add_shadow_pass(FrameGraph& graph, const FrameContext& ctx, bool scene_moves, ShadowPassState& state,
                     EngineResources& engine);
// "geometry": frustum culling, back-to-front order of blended draws, the
// visibility buffer and depth.
void add_geometry_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine,
                       EngineTargets& targets);
// "view distance": FrameBuffers::distance from depth.
void add_view_distance_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine);
// "shade": every pixel (and edge fragment) once from its triangle id;
// pixels where nothing was drawn get the flat background when
// `fill_background` (no plugin composites them); `pixels_shaded` receives
// the count.
void add_shade_pass(FrameGraph& graph, const FrameContext& ctx, const SurfaceLookup& surfaces,
                    const EngineResources& engine, EngineTargets& targets, bool fill_background,
                    uint64_t& pixels_shaded);
// "transparent": the blended draws in view, over the shaded colour.
void add_transparent_pass(FrameGraph& graph, const FrameContext& ctx, const SurfaceLookup& surfaces,
                          const EngineResources& engine, EngineTargets& targets);
// "composite": the plugins' per-pixel composites, in their order.
void add_composite_pass(FrameGraph& graph, const std::vector<Plugin*>& compositors, const EngineResources& engine,
                        EngineTargets& targets);
// "upscale" (an internal size below the output's): the internal colour's
// edge fragments into their pixels, then colour, depth and, when
// `distances`, distance upscaled into `output` (the output-size buffers),
// which targets.color names afterwards; colour through the reversible
// tonemap at `exposure` (upscale.h).
void add_upscale_pass(FrameGraph& graph, const Upscaler& upscaler, const EngineResources& engine,
                      EngineTargets& targets, FrameGraphId<FrameBuffers> output, bool distances, float exposure);
// "resolve": edge fragments into their pixels, exposure, tonemap, 8-bit sRGB.
// `display` (and, for the profile's fixed-point resolve, `fixed_display`)
// is rebuilt when the exposure changes.
void add_resolve_pass(FrameGraph& graph, const FrameContext& ctx, std::unique_ptr<DisplayTransform>& display,
                      std::unique_ptr<Hdr16Display>& fixed_display, EngineTargets& targets);

}  // namespace cr

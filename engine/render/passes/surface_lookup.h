#pragma once
// What the shading passes share: the surface a visibility-buffer id names,
// and the frame's surface shader.
#include "engine/raster/tiled_rasterizer.h"
#include "engine/render/passes/engine_passes.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shade_surface.h"
#include "engine/shading/shadow_map.h"
#include "engine/shading/surface.h"

namespace cr {

class SurfaceLookup {
 public:
  // half_attributes: TriangleSurface's fp16 varyings (profile precision.attributes "float16").
  SurfaceLookup(const Scene& scene, bool half_attributes);
  // The triangle `id` names, in world space, and its material.
  TriangleSurface triangle(const TiledRasterizer& raster, uint32_t id, const Material*& material) const;
  // Hints that triangle() will read these soon, in the order it needs them:
  // the rasterizer's plane of `id`, then (once that is in) the triangle's
  // vertex indices, then (once those are in) its vertices' attributes.
  void prefetch_plane(const TiledRasterizer& raster, uint32_t id) const;
  void prefetch_indices(const TriangleRef& ref) const;
  void prefetch_vertices(const TriangleRef& ref) const;

 private:
  const Scene& scene_;
  bool any_uv1_;  // TEXCOORD_1 is interpolated for materials reading it; most scenes have none
  bool half_attributes_;
};

// The shader of the frame's camera under `light` and `shadow`.
SurfaceShader frame_shader(const FrameContext& ctx, const LightEnvironment& light, const ShadowMap& shadow);

}  // namespace cr

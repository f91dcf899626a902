#include "engine/render/passes/surface_lookup.h"

#include <algorithm>

#include "engine/render/passes/draw_materials.h"
#include "engine/shading/material_eval.h"

namespace cr {

SurfaceLookup::SurfaceLookup(const Scene& scene, bool half_attributes)
    : scene_(scene),
      any_uv1_(std::any_of(scene.materials.begin(), scene.materials.end(),
                           [](const Material& m) { return needs_uv1(m); })),
      half_attributes_(half_attributes) {}

TriangleSurface SurfaceLookup::triangle(const TiledRasterizer& raster, uint32_t id, const Material*& material) const {
  const TriangleRef r = raster.ref(id);
  const Draw& d = scene_.draws[r.draw_index];
  const Primitive& prim = scene_.primitive(d);
  material = &material_of(scene_, prim);
  return TriangleSurface(prim, d, r.triangle_index, r.front_facing, needs_tangent(*material),
                         any_uv1_ && needs_uv1(*material), half_attributes_);
}

void SurfaceLookup::prefetch_plane(const TiledRasterizer& raster, uint32_t id) const {
  const char* p = reinterpret_cast<const char*>(&raster.interp(id));
  __builtin_prefetch(p);
  __builtin_prefetch(p + sizeof(TriangleInterp) - 1);  // it may straddle two lines
}

void SurfaceLookup::prefetch_indices(const TriangleRef& ref) const {
  const Primitive& prim = scene_.primitive(scene_.draws[ref.draw_index]);
  const uint32_t* idx = prim.indices.data() + size_t(ref.triangle_index) * 3;
  __builtin_prefetch(idx);
  __builtin_prefetch(idx + 2);
}

void SurfaceLookup::prefetch_vertices(const TriangleRef& ref) const {
  const Primitive& prim = scene_.primitive(scene_.draws[ref.draw_index]);
  const uint32_t* idx = prim.indices.data() + size_t(ref.triangle_index) * 3;
  for (int k = 0; k < 3; ++k) {
    __builtin_prefetch(&prim.positions[idx[k]]);
    if (!prim.normals.empty()) __builtin_prefetch(&prim.normals[idx[k]]);
    if (!prim.texcoords.empty()) __builtin_prefetch(&prim.texcoords[idx[k]]);
  }
}

SurfaceShader frame_shader(const FrameContext& ctx, const LightEnvironment& light, const ShadowMap& shadow) {
  const Camera& cam = ctx.view.camera;
  // An orthographic view's rays are parallel: shading takes its view vectors
  // from a point 10^7 m back along them, whose directions differ from -forward
  // by less than the scene's extent / 10^7 radians.
  const glm::dvec3 eye = cam.orthographic ? cam.position - glm::dvec3(cam.forward) * 1e7 : cam.position;
  return SurfaceShader(ShadingInputs{&ctx.scene, &light, &shadow, eye, emissive_luminance(ctx.description)});
}

}  // namespace cr

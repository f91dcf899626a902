#include "engine/render/passes/draw_materials.h"

#include "engine/shading/material_eval.h"

namespace cr {

const Material& material_of(const Scene& scene, const Primitive& prim) {
  static const Material kDefault;
  return prim.material >= 0 ? scene.materials[prim.material] : kDefault;
}

CoverageFn alpha_coverage(const Scene& scene, const TiledRasterizer& raster) {
  return [&scene, &raster](uint32_t id, const Barycentrics& bary) {
    const TriangleRef r = raster.ref(id);
    const Draw& d = scene.draws[r.draw_index];
    const Primitive& prim = scene.primitive(d);
    const Material& m = material_of(scene, prim);
    return material_alpha(scene, m, interpolate_uv_color(prim, r.triangle_index, bary, m.base_color.texcoord == 1)) >=
           m.alpha_cutoff;
  };
}

}  // namespace cr

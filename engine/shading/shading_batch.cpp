#include "engine/shading/shading_batch.h"

namespace cr {

void ShadingBatch::add(const SurfaceSample& surface, const MaterialSample& m, float opacity) {
  const int i = count++;
  position[i] = surface.position;
  gx[i] = surface.normal.x;
  gy[i] = surface.normal.y;
  gz[i] = surface.normal.z;
  nx[i] = m.normal.x;
  ny[i] = m.normal.y;
  nz[i] = m.normal.z;
  base_r[i] = m.base_color.r;
  base_g[i] = m.base_color.g;
  base_b[i] = m.base_color.b;
  metallic[i] = m.metallic;
  roughness[i] = m.roughness;
  occlusion[i] = m.occlusion;
  emissive_r[i] = m.emissive.r;
  emissive_g[i] = m.emissive.g;
  emissive_b[i] = m.emissive.b;
  alpha[i] = opacity;
  unlit[i] = m.unlit ? 1.0f : 0.0f;
  any_unlit |= m.unlit;
}

}  // namespace cr

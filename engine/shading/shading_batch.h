#pragma once
// Surface points shaded together, stored as structure-of-arrays so that the
// lighting loops run over contiguous floats the compiler vectorises (one
// lane per point). Filled point by point after the (scalar) material
// evaluation; SurfaceShader::shade_batch lights all points at once.
#include <glm/glm.hpp>

#include "engine/shading/material_eval.h"
#include "engine/shading/surface.h"

namespace cr {

struct ShadingBatch {
  static constexpr int kCapacity = 64;

  int count = 0;
  // Per point (AoS where a scalar consumer takes a vec3: sun_at, the shadow map).
  glm::vec3 position[kCapacity];             // world space
  // The interpolated normal (before the normal map: it drives the shadow
  // bias), as add() stores it; shade_batch makes it unit in one vectorised
  // loop rather than point by point in the scalar path.
  float gx[kCapacity], gy[kCapacity], gz[kCapacity];
  float nx[kCapacity], ny[kCapacity], nz[kCapacity];  // shading normal (normal map applied), unit
  float base_r[kCapacity], base_g[kCapacity], base_b[kCapacity];
  float metallic[kCapacity], roughness[kCapacity], occlusion[kCapacity];
  float emissive_r[kCapacity], emissive_g[kCapacity], emissive_b[kCapacity];
  float alpha[kCapacity];
  // 1 where the point's material is unlit (KHR_materials_unlit): its
  // radiance is emissive_*, and no light reaches it. Read only when any_unlit.
  float unlit[kCapacity];
  bool any_unlit = false;
  // Results of SurfaceShader::shade_batch: radiance towards the camera.
  float out_r[kCapacity], out_g[kCapacity], out_b[kCapacity];

  bool full() const { return count == kCapacity; }
  void clear() {
    count = 0;
    any_unlit = false;
  }
  // Appends one point (the caller checks full() first); `alpha` is the opacity
  // used for blending (1 for OPAQUE and MASK).
  void add(const SurfaceSample& surface, const MaterialSample& m, float opacity);
  glm::vec3 radiance(int i) const { return {out_r[i], out_g[i], out_b[i]}; }
};

}  // namespace cr

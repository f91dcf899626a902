#pragma once
// Specular occlusion from an ambient-occlusion value (Lagarde & de Rousiers
// 2014, "Moving Frostbite to PBR", section 4.10.2):
//   so = saturate((n.v + ao)^exp2(-16 alpha - 1) - 1 + ao),
// alpha = roughness^2 (the course notes' "roughness" is the squared one).
// AO darkens light from every direction alike; a glossy lobe sees the
// unoccluded mirror direction more often than the cosine lobe does, except
// at grazing angles: so ~ ao for rough or grazing, -> 1 for smooth facing
// surfaces. Exactly 1 where ao = 1. Inline, branch-free: vectorises.
#include "engine/core/fast_math.h"

namespace cr {

inline float specular_occlusion(float n_dot_v, float ao, float alpha) {
  const float p = fast_exp2(fast_exp2(-16.0f * alpha - 1.0f) * fast_log2(n_dot_v + ao));
  const float so = p - 1.0f + ao;
  return so > 0.0f ? (so < 1.0f ? so : 1.0f) : 0.0f;
}

}  // namespace cr

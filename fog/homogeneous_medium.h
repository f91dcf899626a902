#pragma once
// Closed forms of a homogeneous medium used per froxel and per pixel, in
// float with cheap exp/log (expm1/log1p are several times slower) and series
// where the direct formula would cancel.
#include <algorithm>
#include <cmath>

#include "engine/core/fast_math.h"

namespace cr {

// 1 - exp(-x) for optical depth x >= 0 (relative error < 1e-6).
inline float opacity_of(float x) {
  const float series = x * (1.0f - x * (0.5f - x * (1.0f / 6.0f)));
  return x < 1e-3f ? series : 1.0f - fast_exp(-x);
}

// Transmittance-proportional sample in [0, dt] of a slice with extinction
// sigma, for u in [0, 1): offset = -log(1 - u (1 - exp(-sigma dt))) / sigma.
// Thin slices use its series in a = sigma dt (error O(a^3) of dt).
// The thin-slice series alone, for a = extinction * dt (branch-free, so loops
// over slices vectorise).
inline float importance_sample_offset_thin(float u, float a, float dt) {
  const float a2 = a * a;
  return dt * (u * (1.0f - 0.5f * a + a2 * (1.0f / 6.0f)) + u * u * (0.5f * a - 0.5f * a2) +
               u * u * u * (a2 * (1.0f / 3.0f)));
}

inline float importance_sample_offset(float u, float extinction, float dt) {
  const float a = extinction * dt;
  if (a < 0.05f) return importance_sample_offset_thin(u, a, dt);
  return std::min(-std::log(1.0f - u * opacity_of(a)) / extinction, dt);
}

}  // namespace cr

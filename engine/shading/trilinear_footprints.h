#pragma once
// The footprints of a batch of lookups through the common sampler (linear
// magnification and minification, linear mips, Repeat or ClampToEdge on each
// axis), as structure of arrays: texture_footprint's levels, texel indices and
// weights for every point at once. Level choice and wraps are selects, so the
// loop vectorises; texture_footprint stays the definition (the same floats
// and indices, tested).
#include <cstdint>

#include "engine/scene/scene.h"
#include "engine/shading/texture_sampler.h"

namespace cr {

// Whether trilinear_footprints handles lookups of `image` through `sampler`:
// the sampler above, and a chain of levels each the last halved (rounded
// down, at least 1), as generate_mips makes them.
bool takes_trilinear_footprints(const Image& image, const Sampler& sampler);

struct TrilinearFootprints {
  static constexpr int kCapacity = TexturePoints::kCapacity;
  static constexpr int kMaxLevels = 32;  // of an int-sized chain: 2^31 down to 1
  // Slot 0 is texture_footprint's level[0]; slot 1 is its level[1] where
  // t != 0 (two levels), else the next level or the last one, unused.
  int32_t level[2][kCapacity];
  uint32_t texel[2][4][kCapacity];  // (x0,y0) (x1,y0) (x0,y1) (x1,y1), as TextureFootprint::Level
  float ax[2][kCapacity], ay[2][kCapacity];
  float t[kCapacity];  // weight of slot 1; 0: slot 0 alone (one level)
};

// The footprints at points (u[i], v[i]) with levels of detail lambda[i],
// i < count <= kCapacity, for an image and sampler that
// takes_trilinear_footprints accepts.
void trilinear_footprints(const Image& image, const Sampler& sampler, const float* u, const float* v,
                          const float* lambda, int count, TrilinearFootprints& out);

}  // namespace cr

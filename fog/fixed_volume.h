#pragma once
// The integrated volume of the fixed-point path (profile "precision":
// "fixed"): 8 bytes a froxel, where the float path's IntegratedFroxel takes 20.
//   in_scatter     radiance added between the near plane and the froxel's far
//                  boundary, hdr16 per channel (relative step 2^-11 from the
//                  night sky to the sun disk, saturating, never negative)
//   optical_depth  log2(1 / transmittance) over the same distance, Q5.11
//                  (code / 2048), saturating at 65535 (depth 32: the
//                  transmittance is 0 beyond 16). The log domain adds
//                  slices' depths, which cannot wrap or increase the
//                  transmittance, and the difference of a froxel's code and
//                  its predecessor's is the slice's extinction, so nothing
//                  else is stored for the composite's in-slice closed form.
// Transmittance is exp2_neg_q15 of the depth (q15): the same function the
// integration's in-scatter steps use, non-increasing in the code.
#include <cstdint>

#include "engine/core/fixed_point.h"
#include "engine/core/hdr16.h"

namespace cr {

struct FixedIntegratedFroxel {
  uint16_t in_scatter[3];
  uint16_t optical_depth;
};
static_assert(sizeof(FixedIntegratedFroxel) == 8);

// Fraction bits of optical_depth, and Q16.16 (exp2_neg_q15's input) to it.
inline constexpr int kOpticalDepthFractionBits = 11;
inline constexpr int kOpticalDepthShift = 16 - kOpticalDepthFractionBits;
// Natural optical depth (extinction x length) per code: ln 2 / 2048.
inline constexpr float kOpticalDepthPerCode = 0.693147181f / float(1 << kOpticalDepthFractionBits);

inline uint16_t transmittance_q15(uint16_t optical_depth) {
  return fx::exp2_neg_q15(uint32_t(optical_depth) << kOpticalDepthShift);
}

}  // namespace cr

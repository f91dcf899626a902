#pragma once
// How the froxels' sun term is stored and blended. The term is the sun's
// shadow visibility in [0, 1] (froxel_passes.h): what lighting writes, the
// history, the still view's mean, the filter's output and the light change.
// The temporal passes are written once over a format:
//   FloatSunTerm  float (profile "precision": "float")
//   Q15SunTerm    q15 codes (value = code / 32768; fully lit air is 32767,
//                 1 saturated), blended by q15 lerps (pmulhrsw) with q15
//                 weights (profile "precision": "fixed"). The visibility
//                 needs no other scale: its range is [0, 1] by definition, and
//                 q15's absolute step (2^-15) is finer there than hdr16's
//                 relative one (2^-11 near 1), so shafts' soft edges keep
//                 their steps (docs/fog.md, "Reduced precision (mobile)").
// FloatSunTerm's operations are the float path's own expressions, so its
// results are those of the code before the formats existed, bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/core/fixed_point.h"

namespace cr {

struct FloatSunTerm {
  using Value = float;
  using Weight = float;
  static constexpr Value kZero = 0.0f;
  static constexpr Value kOne = 1.0f;  // fully lit air
  // Bounds of an empty min/max range.
  static constexpr Value kAbove = INFINITY, kBelow = -INFINITY;
  static Value encode(float v) { return v; }
  static float decode(Value v) { return v; }
  static Weight weight(float w) { return w; }
  // a + (b - a) w.
  static Value lerp(Value a, Value b, Weight w) { return a + (b - a) * w; }
  // The blend's history share (blended - now) scaled by 1 - change.
  static Value scale_history_share(Value now, Value blended, Value change) {
    return now + (blended - now) * (1.0f - std::min(change, 1.0f));
  }
  // A blend whose history is its current value: now + 0 (a zero of either sign becomes +0).
  static Value blend_with_itself(Value now) { return now + 0.0f; }
};

struct Q15SunTerm {
  using Value = uint16_t;
  using Weight = int16_t;
  static constexpr Value kZero = 0;
  static constexpr Value kOne = 32767;  // encode_q15(1)
  static constexpr Value kAbove = 65535, kBelow = 0;
  static Value encode(float v) { return fx::encode_q15(v); }
  static float decode(Value v) { return fx::decode_q15(v); }
  static Weight weight(float w) { return fx::weight_q15(w); }
  static Value lerp(Value a, Value b, Weight w) { return fx::lerp_q15(a, b, w); }
  // 1 - change is (32768 - change) / 32768 exactly; change 0 keeps the blend
  // whole (a weight of 32768 has no q15 code).
  static Value scale_history_share(Value now, Value blended, Value change) {
    return change == 0 ? blended : fx::lerp_q15(now, blended, int16_t(32768 - change));
  }
  static Value blend_with_itself(Value now) { return now; }
};

}  // namespace cr

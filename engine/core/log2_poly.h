#pragma once
// log2(x) by splitting off the exponent and a series for the mantissa,
// written without library calls or branches so that loops calling it
// vectorise (std::log2 does not without -ffast-math); exp2_poly's partner
// for powers in shading loops. Absolute error below 1e-6; exactly 0 at 1 and
// positive above it (so exp2_poly(y * log2_poly(x)) >= 1 for x >= 1, y >= 0).
// x below the least normal float (0, negative, NaN) reads as that float.
#include <bit>
#include <cfloat>
#include <cstdint>

namespace cr {

inline float log2_poly(float x) {
  x = x > FLT_MIN ? (x < FLT_MAX ? x : FLT_MAX) : FLT_MIN;
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  const float e = float(int32_t(bits >> 23) - 127);
  const float m = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // [1, 2)
  // log2(m) = 2/ln2 atanh(t), t = (m - 1)/(m + 1) in [0, 1/3]: odd series to t^9 (remainder < 2e-7).
  const float t = (m - 1.0f) / (m + 1.0f);
  const float t2 = t * t;
  const float s = t * (1.0f + t2 * (1.0f / 3.0f + t2 * (1.0f / 5.0f + t2 * (1.0f / 7.0f + t2 * (1.0f / 9.0f)))));
  return e + 2.885390082f * s;
}

}  // namespace cr

#pragma once
// log(x) for x >= 1 (the froxel slice encoding's argument) without a libm
// call: x = m 2^e with m in [sqrt(1/2), sqrt(2)), and the Cephes logf
// minimax polynomial in m - 1 (relative error about 1e-7, like logf).
// Branch-free and libm-free so loops over a column's slices vectorise; plain
// float and integer operations, so results are the same on every thread.
#include <bit>
#include <cstdint>

namespace cr {

inline float fast_log(float x) {
  const int32_t bits = std::bit_cast<int32_t>(x);
  // Mantissa in [1, 2); halved above sqrt(2), which moves one into the exponent.
  float m = std::bit_cast<float>((bits & 0x007fffff) | 0x3f800000);
  const int32_t high = m > 1.41421356f ? 1 : 0;
  m = high ? m * 0.5f : m;
  const float e = float(((bits >> 23) & 0xff) - 127 + high);
  const float f = m - 1.0f;
  const float z = f * f;
  float p = 7.0376836292e-2f;
  p = p * f - 1.1514610310e-1f;
  p = p * f + 1.1676998740e-1f;
  p = p * f - 1.2420140846e-1f;
  p = p * f + 1.4249322787e-1f;
  p = p * f - 1.6668057665e-1f;
  p = p * f + 2.0000714765e-1f;
  p = p * f - 2.4999993993e-1f;
  p = p * f + 3.3333331174e-1f;
  float y = p * f * z;
  y = y + e * -2.12194440e-4f;
  y = y - 0.5f * z;
  return (f + y) + e * 0.693359375f;
}

}  // namespace cr

#pragma once
// hdr16: radiance and luminance in 16 bits, from the night sky (~1e-4 cd/m^2)
// to the sun disk (~1e9 cd/m^2). An unsigned minifloat: 6-bit exponent E,
// 10-bit mantissa m, exponent bias 31, no sign, no infinity, no NaN:
//   E >= 1: 2^(E - 31) * (1 + m / 1024), normals in [2^-30, 2^33 - 2^22]
//   E == 0: 2^-30 * m / 1024 (denormals, steps of 2^-40)
// Gradual underflow keeps one rule for every input: the nearest code, ties to
// even (an IEEE conversion with saturation instead of infinity). Codes are
// monotone in the value, so they compare and sort like the values. Relative
// error <= 2^-11 on the normal range. Above the top code everything
// saturates to 0xFFFF (+inf included); negatives, -0 and NaN give 0.
#include <algorithm>
#include <bit>
#include <cstdint>

namespace cr::fx {

inline constexpr float kHdr16Max = 0x1.ffcp32f;        // decode_hdr16(0xFFFF), ~8.59e9
inline constexpr float kHdr16MinNormal = 0x1p-30f;     // decode_hdr16(0x0400), ~9.3e-10
inline constexpr float kHdr16MinDenormal = 0x1p-40f;   // decode_hdr16(0x0001), ~9.1e-13

// From the float's bits: a normal result is the float re-biased (127 -> 31)
// with its mantissa rounded from 23 to 10 bits; a carry out of the mantissa
// steps the exponent, as it should. A denormal result is the float's
// significand shifted down to steps of 2^-40, rounded the same way.
inline uint16_t encode_hdr16(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  if (b > 0x7F800000u) return 0;  // NaN, and everything with the sign bit set
  // Round a right shift by s to nearest, ties to even: add just under half,
  // plus one when the kept low bit is odd.
  auto shift_round = [](uint32_t v, uint32_t s) { return (v + (1u << (s - 1)) - 1 + ((v >> s) & 1)) >> s; };
  if (b >= (97u << 23))  // x >= 2^-30: float exponent 97 is hdr16 exponent 1
    return uint16_t(std::min<uint32_t>(shift_round(b - (96u << 23), 13), 0xFFFF));
  const uint32_t s = 110 - (b >> 23);  // x = significand * 2^(exponent - 150), code = x * 2^40
  if (s > 24) return 0;                // x < 2^-41: below half the smallest denormal
  return uint16_t(shift_round((b & 0x7FFFFFu) | 0x800000u, s));
}

// Exact: a normal code is a float's bits re-biased; a denormal is m * 2^-40.
// Integer-only for normals, and no float denormal anywhere, so DAZ/FTZ modes
// cannot change it.
inline float decode_hdr16(uint16_t c) {
  return c >= 0x400 ? std::bit_cast<float>((uint32_t(c) << 13) + (96u << 23)) : float(c) * 0x1p-40f;
}

}  // namespace cr::fx

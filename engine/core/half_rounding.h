#pragma once
// Rounding a float to the nearest IEEE half-precision value (fp16: 10-bit
// mantissa, normals from 2^-14, denormals in steps of 2^-24), ties to even,
// returned as a float: what a phone's mediump (fp16) varyings keep of an
// interpolated attribute. Beyond fp16's largest finite value (65504) it
// saturates there instead of becoming infinite; NaN stays NaN. Integer work
// on the bits (plus one rounding for denormals), no F16C needed.
#include <bit>
#include <cmath>
#include <cstdint>

namespace cr {

inline float round_to_half(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  const uint32_t sign = b & 0x80000000u, magnitude = b & 0x7FFFFFFFu;
  if (magnitude > 0x7F800000u) return x;  // NaN
  if (magnitude >= 0x38800000u) {  // |x| >= 2^-14: keep 10 of the 23 mantissa bits, ties to even
    const uint32_t rounded = (magnitude + 0xFFFu + ((magnitude >> 13) & 1u)) & ~0x1FFFu;
    return std::bit_cast<float>(sign | (rounded > 0x477FE000u ? 0x477FE000u : rounded));  // 65504 at most
  }
  return std::copysign(std::nearbyint(std::abs(x) * 0x1p24f) * 0x1p-24f, x);  // denormal steps of 2^-24
}

}  // namespace cr

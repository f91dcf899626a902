#pragma once
// fx::encode_hdr16 (engine/core/hdr16.h) without branches, so that a loop
// over it vectorises (the fixed-point integration encodes three channels a
// froxel). Both paths are computed and one is selected; the results equal
// encode_hdr16's for every float, bit for bit (tests/fog/test_fog_fixed.cpp).
// Until the fixed-point core has a vector form of its own.
#include <algorithm>
#include <bit>
#include <cstdint>

namespace cr {

inline uint16_t encode_hdr16_branch_free(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  // Round a right shift by s to nearest, ties to even.
  auto shift_round = [](uint32_t v, uint32_t s) { return (v + (1u << (s - 1)) - 1 + ((v >> s) & 1)) >> s; };
  const uint32_t normal = std::min<uint32_t>(shift_round(b - (96u << 23), 13), 0xFFFF);
  // Denormal codes: the significand in steps of 2^-40; a shift of 25 or
  // more leaves 0, as encode_hdr16's "below half the smallest denormal".
  const uint32_t shift = std::min<uint32_t>(110 - std::min<uint32_t>(b >> 23, 96), 25);
  const uint32_t denormal = shift_round((b & 0x7FFFFFu) | 0x800000u, shift);
  const uint32_t code = b >= (97u << 23) ? normal : denormal;
  return uint16_t(b > 0x7F800000u ? 0u : code);  // NaN, and everything with the sign bit set
}

}  // namespace cr

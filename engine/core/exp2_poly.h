#pragma once
// 2^x by range reduction and a polynomial, written without library calls or
// branches so that loops calling it vectorise (std::exp2 does not without
// -ffast-math). Relative error below 2e-7 (a float ulp or two) for x in
// [-126, 126]; x is clamped to that range, NaN reads as -126.
#include <bit>
#include <cmath>
#include <cstdint>

namespace cr {

inline float exp2_poly(float x) {
  x = x > -126.0f ? (x < 126.0f ? x : 126.0f) : -126.0f;
  // x = i + f with f in [-0.5, 0.5]; 2^f = e^(f ln 2) by its Taylor series to
  // degree 6 (remainder (0.35)^7 / 7! < 2e-7).
  const float i = std::floor(x + 0.5f);
  const float t = (x - i) * 0.693147181f;
  const float p =
      1.0f + t * (1.0f + t * (0.5f + t * (1.0f / 6.0f + t * (1.0f / 24.0f + t * (1.0f / 120.0f + t * (1.0f / 720.0f))))));
  const float scale = std::bit_cast<float>(uint32_t(int32_t(i) + 127) << 23);
  return p * scale;
}

}  // namespace cr

#pragma once
// Branch-light approximations for per-pixel paths, where a libm call per pixel
// would dominate the composite's budget. Both are deterministic (plain IEEE ops).
#include <bit>
#include <cmath>
#include <cstdint>

#include "engine/core/math_constants.h"

namespace cr {

// acos on [-1, 1], |error| <= 2e-8 rad (Abramowitz & Stegun 4.4.46).
inline float fast_acos(float x) {
  const float ax = std::fabs(x) < 1.0f ? std::fabs(x) : 1.0f;
  float p = -0.0012624911f;
  p = p * ax + 0.0066700901f;
  p = p * ax - 0.0170881256f;
  p = p * ax + 0.0308918810f;
  p = p * ax - 0.0501743046f;
  p = p * ax + 0.0889789874f;
  p = p * ax - 0.2145988016f;
  p = p * ax + 1.5707963050f;
  const float a = std::sqrt(1.0f - ax) * p;
  return x >= 0.0f ? a : kPi - a;
}

// exp(x) for x <= 0 (ray-march densities and transmittances), relative error
// < 2e-7, exactly 0 at or below -87. Cody-Waite reduction to 2^n * exp(r),
// |r| <= ln2/2, and a degree-6 Taylor polynomial; plain arithmetic, so loops
// over it vectorize and results are the same on every thread.
inline float fast_exp_neg(float x) {
  const bool underflow = !(x > -87.0f);  // also catches NaN
  x = underflow ? 0.0f : (x < 0.0f ? x : 0.0f);
  const float shift = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
  const float n = (x * 1.44269504f + shift) - shift;
  const float r = (x - n * 0.693145752f) - n * 1.42860677e-6f;
  float p = 1.0f / 720.0f;
  p = p * r + 1.0f / 120.0f;
  p = p * r + 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  const int32_t bits = (int32_t(n) + 127) << 23;
  const float e = p * std::bit_cast<float>(bits);
  return underflow ? 0.0f : e;
}

// (1 - exp(-x)) / x for x >= 0: the segment integral of Hillaire's analytic
// step, exact in the limit x -> 0 (vacuum) where the direct form cancels.
inline float one_minus_exp_over_x(float x, float exp_neg_x) {
  if (x < 0.1f)  // series: the direct form loses digits to cancellation here
    return 1.0f - x * (0.5f - x * (1.0f / 6.0f - x * (1.0f / 24.0f - x * (1.0f / 120.0f - x * (1.0f / 720.0f)))));
  return (1.0f - exp_neg_x) / x;
}

}  // namespace cr

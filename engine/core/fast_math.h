#pragma once
// Fast approximations of exp, log, exp2, log2 and acos for per-froxel,
// per-pixel and per-sample loops, where a libm call would dominate the cost
// (and, without -ffast-math, keeps the loop from vectorising). Each is plain
// IEEE float arithmetic without library calls and nearly free of branches:
// deterministic, the same on every thread and at every vector width.
//
// One name per function. The two exps are not one function twice: they
// differ in the last bits (another polynomial and another split of ln 2) and
// below -87 (fast_exp_neg gives exactly 0, fast_exp holds at exp(-87)),
// and the frames made with each depend on those bits, so each stays as it
// is. Likewise fast_log (natural, Cephes) and fast_log2 (atanh series) are
// different approximations, not one scaled.
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "engine/core/math_constants.h"

namespace cr {

// exp(x) without a libm call: Cody-Waite reduction x = n ln2 + r and the
// Cephes expf minimax polynomial on |r| <= ln2/2 (relative error about 2e-7,
// like expf), for the whole float range.
inline float fast_exp(float x) {
  // Below -87 the result is under the smallest normal float: flush to it.
  x = std::min(std::max(x, -87.0f), 88.0f);
  // Round x / ln2 to the nearest integer (|x / ln2| < 2^22, so adding and
  // removing 1.5 * 2^23 rounds in the current, round-to-nearest mode).
  const float n = (x * 1.44269504089f + 12582912.0f) - 12582912.0f;
  const float r = (x - n * 0.693359375f) - n * -2.12194440e-4f;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = p * (r * r) + r + 1.0f;
  const int32_t bits = (int32_t(n) + 127) << 23;  // 2^n
  return p * std::bit_cast<float>(bits);
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

// 2^x by range reduction and a polynomial. Relative error below 2e-7 (a float
// ulp or two) for x in [-126, 126]; x is clamped to that range, NaN reads as
// -126.
inline float fast_exp2(float x) {
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

// log(x) for x >= 1 (the froxel slice encoding's argument): x = m 2^e with m
// in [sqrt(1/2), sqrt(2)), and the Cephes logf minimax polynomial in m - 1
// (relative error about 1e-7, like logf).
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

// log2(x) by splitting off the exponent and a series for the mantissa;
// fast_exp2's partner for powers in shading loops. Absolute error below
// 1e-6; exactly 0 at 1 and positive above it (so fast_exp2(y * fast_log2(x))
// >= 1 for x >= 1, y >= 0). x below the least normal float (0, negative, NaN)
// reads as that float.
inline float fast_log2(float x) {
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

// (1 - exp(-x)) / x for x >= 0: the segment integral of Hillaire's analytic
// step, exact in the limit x -> 0 (vacuum) where the direct form cancels.
inline float one_minus_exp_over_x(float x, float exp_neg_x) {
  if (x < 0.1f)  // series: the direct form loses digits to cancellation here
    return 1.0f - x * (0.5f - x * (1.0f / 6.0f - x * (1.0f / 24.0f - x * (1.0f / 120.0f - x * (1.0f / 720.0f)))));
  return (1.0f - exp_neg_x) / x;
}

}  // namespace cr

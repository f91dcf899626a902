#pragma once
// Fixed-point arithmetic for the reduced-precision ("mobile") per-pixel
// kernels: LUT sampling, sky and fog composite, resolve. These scalar
// functions are the definitions; the vector forms (fixed_simd.h) equal them
// bit for bit. Formats, error bounds and costs: docs/fixed_point.md.
//
// Rounding: conversions from float round to nearest, ties to even: the
// default rounding mode, which the engine never changes. Scalar (nearbyint,
// roundss) and vector forms (cvtps2dq) both round in the current mode, so
// they agree bit for bit under any. Integer products round half up, as
// pmulhrsw does.
// Every conversion saturates and maps NaN to 0. No operation overflows a
// signed type: products are formed in int32/int64 or unsigned.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cr::fx {

namespace detail {

// Clamps x to [lo, hi] with NaN -> 0 (comparisons with NaN are false).
inline float clamp_nan0(float x, float lo, float hi) {
  if (!(x == x)) return 0.0f;
  return x < lo ? lo : (x > hi ? hi : x);
}

}  // namespace detail

// ---- q15: Q0.15, value = code / 32768, codes 0..32767 -----------------------
// 15 bits, not 16, so that the difference of two codes fits int16 and
// pmulhrsw interpolates it exactly (lerp_q15).

// x * 32768 is exact (a power-of-two scale), so the result is the nearest
// code: |decode_q15(encode_q15(x)) - x| <= 2^-16 on [0, 32767/32768].
inline uint16_t encode_q15(float x) {
  return uint16_t(std::nearbyint(detail::clamp_nan0(x * 32768.0f, 0.0f, 32767.0f)));
}

inline float decode_q15(uint16_t c) { return float(c) * (1.0f / 32768.0f); }

// A weight in [0, 1] (a bilinear fraction is < 1): round(w * 32768), with
// 1.0 saturating to 32767. The same rounding as encode_q15.
inline int16_t weight_q15(float w) { return int16_t(encode_q15(w)); }

// Exactly x86 pmulhrsw: (a * b + 2^14) >> 15, arithmetic shift, truncated to
// 16 bits. Only -32768 * -32768 leaves the range: 32768 wraps to -32768,
// as the instruction does.
inline int16_t mul_round_q15(int16_t a, int16_t b) {
  return int16_t((int32_t(a) * int32_t(b) + 0x4000) >> 15);
}

// a + (b - a) * w for q15 a, b and weight w in 0..32767: the difference fits
// int16 and w < 32768, so |(b - a) * w / 32768| < |b - a| and the rounded
// step never passes b: the result is in [min(a, b), max(a, b)], monotone in
// w, a at w = 0, within 0.5 code of the exact value (rounding half up).
// At w = 32767 it is b only for -16384 < b - a <= 16384, one code short beyond.
inline uint16_t lerp_q15(uint16_t a, uint16_t b, int16_t w) {
  return uint16_t(a + mul_round_q15(int16_t(b - a), w));
}

// ---- unorm16: value = code / 65535 ------------------------------------------

// x * 65535 is exact in double (24 + 16 bits), so the result is the nearest
// code: |c / 65535 - x| <= 0.5 / 65535 on [0, 1].
inline uint16_t encode_unorm16(float x) {
  const double y = double(detail::clamp_nan0(x, 0.0f, 1.0f)) * 65535.0;
  return uint16_t(std::nearbyint(y));
}

// The float nearest to c / 65535 (one correctly rounded division).
inline float decode_unorm16(uint16_t c) { return float(c) / 65535.0f; }

// round(a * b / 65535), exactly, for every a and b: with t = a * b + 2^15,
// (t + (t >> 16)) >> 16 (Blinn's identity for 2^n - 1 denominators). a * b /
// 65535 is never a half-integer (65535 is odd), so there are no ties. t and
// t + (t >> 16) stay below 2^32.
inline uint16_t mul_unorm16(uint16_t a, uint16_t b) {
  const uint32_t t = uint32_t(a) * uint32_t(b) + 0x8000u;
  return uint16_t((t + (t >> 16)) >> 16);
}

// ---- Q1.14: value = code / 16384, range [-2, 2 - 2^-14] ---------------------

inline int16_t encode_q1_14(float x) {
  return int16_t(std::nearbyint(detail::clamp_nan0(x * 16384.0f, -32768.0f, 32767.0f)));
}

inline float decode_q1_14(int16_t c) { return float(c) * (1.0f / 16384.0f); }

// ---- Q16.16: value = code / 65536, range [-32768, 32768 - 2^-16] -------------

// x * 65536 is exact unless it overflows to infinity, which saturates.
inline int32_t encode_q16_16(float x) {
  const float y = x * 65536.0f;
  if (!(y == y)) return 0;
  if (y >= 2147483648.0f) return std::numeric_limits<int32_t>::max();
  if (y <= -2147483648.0f) return std::numeric_limits<int32_t>::min();
  return int32_t(std::nearbyint(y));
}

// The float nearest to c / 65536 (exact for |c| <= 2^24).
inline float decode_q16_16(int32_t c) { return float(c) * (1.0f / 65536.0f); }

// a * b / 65536 rounded half up, saturated to the int32 range. The product
// (at most 2^62 in magnitude) is formed in int64.
inline int32_t mul_q16_16(int32_t a, int32_t b) {
  const int64_t p = (int64_t(a) * int64_t(b) + 0x8000) >> 16;
  return int32_t(std::clamp<int64_t>(p, std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::max()));
}

// 1 / x for x > 0, both Q16.16 unsigned: round(2^32 / x), half up, saturated
// to 0xFFFFFFFF where 1 / x does not fit (codes 0 and 1, x <= 2^-16). An
// exact 64-bit division rather than a table and Newton step: it is exactly
// rounded, and a resolve divides once a pixel, where one div (about 2 ns)
// costs less than the lookup, two multiplies and the correction step of an
// exactly-rounded Newton reciprocal would save.
inline uint32_t reciprocal_q16_16(uint32_t x) {
  if (x <= 1) return 0xFFFFFFFFu;
  return uint32_t(((uint64_t(1) << 32) + (x >> 1)) / x);
}

// ---- exp2 and log2 ----------------------------------------------------------

namespace detail {

// Double-precision exp(-t) for t in [0, 1] and ln(y) for y near 1, for the
// tables below. constexpr series (no libm), so the tables are compile-time
// constants, identical with every compiler and library.
constexpr double exp_neg_series(double t) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 30; ++k) {
    term *= -t / k;
    sum += term;
  }
  return sum;
}

constexpr double ln_series(double y) {
  const double s = (y - 1.0) / (y + 1.0), s2 = s * s;  // ln y = 2 atanh(s)
  double sum = 0.0, power = s;
  for (int k = 1; k < 80; k += 2) {  // |s| <= 1/3: 3^-80 is far below 2^-53
    sum += power / k;
    power *= s2;
  }
  return 2.0 * sum;
}

inline constexpr double kLn2 = 0.69314718055994530942;

// 2^-(i / 256) and 2^-(i / 65536) for i in 0..255, Q1.31 (2^0 = 2^31).
constexpr std::array<uint32_t, 256> exp2_neg_table(double step) {
  std::array<uint32_t, 256> t{};
  for (int i = 0; i < 256; ++i) t[i] = uint32_t(exp_neg_series(i * step * kLn2) * 2147483648.0 + 0.5);
  return t;
}
inline constexpr std::array<uint32_t, 256> kExp2NegHi = exp2_neg_table(1.0 / 256.0);
inline constexpr std::array<uint32_t, 256> kExp2NegLo = exp2_neg_table(1.0 / 65536.0);

// For log2 of a mantissa m in [1, 2) with top fraction bits i = floor((m - 1)
// * 256): kLogRecip[i] = round(2^31 / c) with c = 1 + (i + 0.5) / 256, so
// m * kLogRecip[i] / 2^31 = 1 + v, |v| < 2^-9; kLog2Recip[i] is
// -log2(kLogRecip[i] / 2^31) in Q32, of the rounded reciprocal, so the table
// adds no error beyond its own rounding (2^-33).
constexpr std::array<uint32_t, 256> log_recip_table() {
  std::array<uint32_t, 256> t{};
  for (uint64_t i = 0; i < 256; ++i) t[i] = uint32_t(((uint64_t(1) << 40) + (513 + 2 * i) / 2) / (513 + 2 * i));
  return t;
}
inline constexpr std::array<uint32_t, 256> kLogRecip = log_recip_table();
constexpr std::array<int64_t, 256> log2_recip_table() {
  std::array<int64_t, 256> t{};
  for (int i = 0; i < 256; ++i) {
    const double l = -ln_series(kLogRecip[i] / 2147483648.0) / kLn2 * 4294967296.0;
    t[i] = int64_t(l + 0.5);
  }
  return t;
}
inline constexpr std::array<int64_t, 256> kLog2Recip = log2_recip_table();

}  // namespace detail

// 2^-x as q15 for x >= 0 in Q16.16 (unsigned). x = n + f: 2^-f from two
// 256-entry Q1.31 tables (high and low 8 bits of f) multiplied, then shifted
// by n with rounding half up. The Q1.31 product is within 2^-30 of 2^-f, so
// the result is within 0.5 + 2^-15 code of 32768 * 2^-x (measured over
// every x in [0, 17): 0.500004, 3 results not the nearest code). 2^0
// saturates to 32767; the result is 0 for x > 16 (2^-x below half a code);
// x = 16 gives 1 (0.5 rounds up).
inline uint16_t exp2_neg_q15(uint32_t x_q16_16) {
  const uint32_t n = x_q16_16 >> 16;
  if (n > 16) return 0;
  const uint32_t f = x_q16_16 & 0xFFFFu;
  const uint64_t p = uint64_t(detail::kExp2NegHi[f >> 8]) * detail::kExp2NegLo[f & 0xFFu];
  const uint64_t m = (p + (uint64_t(1) << 30)) >> 31;  // 2^-f in Q1.31
  const uint32_t s = 16 + n;                           // Q1.31 -> q15, then 2^-n
  return uint16_t(std::min<uint64_t>((m + (uint64_t(1) << (s - 1))) >> s, 32767));
}

// log2 of a Q16.16 value x > 0 (x / 65536 in [2^-16, 2^16)), Q16.16 signed,
// rounded half up: in [-16, 16] * 65536. For an integer n, log2(n) is
// log2_q16_16(n) + (16 << 16). x = 0 gives INT32_MIN (-infinity).
// x = 2^e * m, m in [1, 2); m times a table reciprocal near 1 / m leaves
// 1 + v with |v| < 2^-9, and ln(1 + v) ~ v - v^2 / 2 (the next term is
// below 2^-28.5). Within 0.5 + 2^-12 code of the exact log2 (measured:
// 0.50019; about 1 result in 36000 is not the nearest code).
inline int32_t log2_q16_16(uint32_t x) {
  if (x == 0) return std::numeric_limits<int32_t>::min();
  const int e = 31 - std::countl_zero(x);
  const uint32_t m = x << (31 - e);  // m / 2^31 in [1, 2)
  const uint32_t i = (m >> 23) & 0xFFu;
  // m * r / 2^62 = 1 + v; v in Q32 (|v| < 2^23 in that scale).
  const int64_t v = int64_t(uint64_t(m) * detail::kLogRecip[i] - (uint64_t(1) << 62)) >> 30;
  const int64_t ln = v - ((v * v) >> 33);                     // Q32
  const int64_t log2_1pv = (ln * int64_t(6196328019)) >> 32;  // times 1 / ln 2 in Q32
  const int64_t q32 = (int64_t(e - 16) << 32) + detail::kLog2Recip[i] + log2_1pv;
  return int32_t((q32 + 0x8000) >> 16);
}

}  // namespace cr::fx

#pragma once
// 8- and 16-lane forms of the q15 operations of fixed_point.h, equal to the
// scalar definitions lane by lane, bit for bit. pmulhrsw (SSSE3, in every
// supported baseline) is mul_round_q15 itself, and the 15-bit payload of q15
// makes a lerp one subtract, one pmulhrsw and one add.
//
// The 8-lane forms (16-byte vectors) exist at every baseline. The 16-lane
// integer forms and the F32x8 conversions (32-byte vectors) exist where AVX2
// does (x86-64-v3 and up): below it, GCC warns at every call that passes a
// 32-byte vector, and they would be two SSE halves anyway.
// Instruction mapping and costs: docs/fixed_point.md.
#include <immintrin.h>

#include <cstdint>

namespace cr::fx {

using U16x8 = uint16_t __attribute__((vector_size(16)));
using I16x8 = int16_t __attribute__((vector_size(16)));
using F32x4 = float __attribute__((vector_size(16)));

inline I16x8 mul_round_q15(I16x8 a, I16x8 b) { return I16x8(_mm_mulhrs_epi16(__m128i(a), __m128i(b))); }

// The subtraction and addition are modulo 2^16, like the scalar's int16 and
// uint16 truncations: for a, b, w in 0..32767, b - a read as int16 is the
// exact difference and the sum lands in [min(a, b), max(a, b)].
inline U16x8 lerp_q15(U16x8 a, U16x8 b, I16x8 w) { return a + U16x8(mul_round_q15(I16x8(b - a), w)); }

namespace detail {

// The scalar encode_q15's steps on 4 lanes: scale by 32768 (exact), clamp
// with NaN -> 0 (maxps returns its second operand, 0, when the first is
// NaN), convert to int32 rounding in the current mode, as nearbyint does.
inline __m128i encode_q15_i32(F32x4 x) {
  const __m128 y = _mm_min_ps(_mm_max_ps(_mm_mul_ps(__m128(x), _mm_set1_ps(32768.0f)), _mm_setzero_ps()),
                              _mm_set1_ps(32767.0f));
  return _mm_cvtps_epi32(y);
}

}  // namespace detail

// Eight floats, lanes 0-3 from lo and 4-7 from hi; packusdw joins them
// (0..32767: nothing saturates there).
inline U16x8 encode_q15(F32x4 lo, F32x4 hi) {
  return U16x8(_mm_packus_epi32(detail::encode_q15_i32(lo), detail::encode_q15_i32(hi)));
}

// float(c) / 32768, exact: zero-extend (pmovzxwd, punpckhwd), convert, scale.
inline void decode_q15(U16x8 c, F32x4& lo, F32x4& hi) {
  const __m128i u = __m128i(c);
  lo = F32x4(_mm_cvtepi32_ps(_mm_cvtepu16_epi32(u))) * (1.0f / 32768.0f);
  hi = F32x4(_mm_cvtepi32_ps(_mm_unpackhi_epi16(u, _mm_setzero_si128()))) * (1.0f / 32768.0f);
}

#if defined(__AVX2__)

using U16x16 = uint16_t __attribute__((vector_size(32)));
using I16x16 = int16_t __attribute__((vector_size(32)));
using F32x8 = float __attribute__((vector_size(32)));

inline I16x16 mul_round_q15(I16x16 a, I16x16 b) { return I16x16(_mm256_mulhrs_epi16(__m256i(a), __m256i(b))); }

inline U16x16 lerp_q15(U16x16 a, U16x16 b, I16x16 w) { return a + U16x16(mul_round_q15(I16x16(b - a), w)); }

// encode_q15(F32x4, F32x4) in one 8-lane pass.
inline U16x8 encode_q15(F32x8 x) {
  const __m256 y = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(__m256(x), _mm256_set1_ps(32768.0f)), _mm256_setzero_ps()),
                                 _mm256_set1_ps(32767.0f));
  const __m256i i = _mm256_cvtps_epi32(y);
  return U16x8(_mm_packus_epi32(_mm256_castsi256_si128(i), _mm256_extracti128_si256(i, 1)));
}

inline F32x8 decode_q15(U16x8 c) {
  return F32x8(_mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(__m128i(c)))) * (1.0f / 32768.0f);
}

#endif

}  // namespace cr::fx

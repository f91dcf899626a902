#pragma once
// Eight-lane integer and float vectors for the rasterizer's 8-pixel spans:
// one AVX2 register where the build's baseline has AVX2 (CR_ARCH x86-64-v3
// and up), a pair of SSE2 registers otherwise. Every operation is lane-wise
// and exact (integers) or a single IEEE operation (floats), so both give the
// same bits. With AVX-512VL, stores under a lane mask write only those lanes.
#include <immintrin.h>

#include <cstdint>

namespace cr::span8 {

#if defined(__AVX2__)

struct I {
  __m256i v;
};
struct F {
  __m256 v;
};

inline I iset1(int32_t x) { return {_mm256_set1_epi32(x)}; }
inline I lanes() { return {_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)}; }
inline I bit_values() { return {_mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)}; }
// a * lane for lanes 0..7.
inline I steps(int32_t a) { return {_mm256_mullo_epi32(_mm256_set1_epi32(a), lanes().v)}; }
inline I operator+(I a, I b) { return {_mm256_add_epi32(a.v, b.v)}; }
inline I operator|(I a, I b) { return {_mm256_or_si256(a.v, b.v)}; }
inline I operator&(I a, I b) { return {_mm256_and_si256(a.v, b.v)}; }
inline I andnot(I a, I b) { return {_mm256_andnot_si256(a.v, b.v)}; }  // ~a & b
inline I sign(I a) { return {_mm256_srai_epi32(a.v, 31)}; }             // all ones where negative
inline I operator==(I a, I b) { return {_mm256_cmpeq_epi32(a.v, b.v)}; }
// Lane mask (8 bits) of the sign bits.
inline unsigned bits(I a) { return unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(a.v))); }
inline F fset1(float x) { return {_mm256_set1_ps(x)}; }
inline F to_float(I a) { return {_mm256_cvtepi32_ps(a.v)}; }
inline F operator+(F a, F b) { return {_mm256_add_ps(a.v, b.v)}; }
inline F operator*(F a, F b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline F max(F a, F b) { return {_mm256_max_ps(a.v, b.v)}; }  // maxps: b where unordered
inline F min(F a, F b) { return {_mm256_min_ps(a.v, b.v)}; }  // minps: b where unordered
inline I round_to_int(F a) { return {_mm256_cvtps_epi32(a.v)}; }  // nearest, ties to even (the default mode)
inline I bits_of(F a) { return {_mm256_castps_si256(a.v)}; }
inline F float_of(I a) { return {_mm256_castsi256_ps(a.v)}; }
inline I greater(F a, F b) { return {_mm256_castps_si256(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ))}; }
inline F load(const float* p) { return {_mm256_loadu_ps(p)}; }
inline I load(const uint32_t* p) { return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))}; }
#if defined(__AVX512VL__)
inline void store(float* p, F v, I, unsigned m) { _mm256_mask_storeu_ps(p, __mmask8(m), v.v); }
inline void store(uint32_t* p, I v, I, unsigned m) { _mm256_mask_storeu_epi32(p, __mmask8(m), v.v); }
#else
inline void store(float* p, F v, I mask, unsigned) {
  _mm256_storeu_ps(p, _mm256_blendv_ps(_mm256_loadu_ps(p), v.v, _mm256_castsi256_ps(mask.v)));
}
inline void store(uint32_t* p, I v, I mask, unsigned) {
  __m256i* q = reinterpret_cast<__m256i*>(p);
  _mm256_storeu_si256(q, _mm256_blendv_epi8(_mm256_loadu_si256(q), v.v, mask.v));
}
#endif

#else  // SSE2

struct I {
  __m128i lo, hi;
};
struct F {
  __m128 lo, hi;
};

inline I iset1(int32_t x) { return {_mm_set1_epi32(x), _mm_set1_epi32(x)}; }
inline I lanes() { return {_mm_setr_epi32(0, 1, 2, 3), _mm_setr_epi32(4, 5, 6, 7)}; }
inline I bit_values() { return {_mm_setr_epi32(1, 2, 4, 8), _mm_setr_epi32(16, 32, 64, 128)}; }
inline I steps(int32_t a) { return {_mm_setr_epi32(0, a, 2 * a, 3 * a), _mm_setr_epi32(4 * a, 5 * a, 6 * a, 7 * a)}; }
inline I operator+(I a, I b) { return {_mm_add_epi32(a.lo, b.lo), _mm_add_epi32(a.hi, b.hi)}; }
inline I operator|(I a, I b) { return {_mm_or_si128(a.lo, b.lo), _mm_or_si128(a.hi, b.hi)}; }
inline I operator&(I a, I b) { return {_mm_and_si128(a.lo, b.lo), _mm_and_si128(a.hi, b.hi)}; }
inline I andnot(I a, I b) { return {_mm_andnot_si128(a.lo, b.lo), _mm_andnot_si128(a.hi, b.hi)}; }
inline I sign(I a) { return {_mm_srai_epi32(a.lo, 31), _mm_srai_epi32(a.hi, 31)}; }
inline I operator==(I a, I b) { return {_mm_cmpeq_epi32(a.lo, b.lo), _mm_cmpeq_epi32(a.hi, b.hi)}; }
inline unsigned bits(I a) {
  return unsigned(_mm_movemask_ps(_mm_castsi128_ps(a.lo))) | unsigned(_mm_movemask_ps(_mm_castsi128_ps(a.hi))) << 4;
}
inline F fset1(float x) { return {_mm_set1_ps(x), _mm_set1_ps(x)}; }
inline F to_float(I a) { return {_mm_cvtepi32_ps(a.lo), _mm_cvtepi32_ps(a.hi)}; }
inline F operator+(F a, F b) { return {_mm_add_ps(a.lo, b.lo), _mm_add_ps(a.hi, b.hi)}; }
inline F operator*(F a, F b) { return {_mm_mul_ps(a.lo, b.lo), _mm_mul_ps(a.hi, b.hi)}; }
inline F max(F a, F b) { return {_mm_max_ps(a.lo, b.lo), _mm_max_ps(a.hi, b.hi)}; }
inline F min(F a, F b) { return {_mm_min_ps(a.lo, b.lo), _mm_min_ps(a.hi, b.hi)}; }
inline I round_to_int(F a) { return {_mm_cvtps_epi32(a.lo), _mm_cvtps_epi32(a.hi)}; }
inline I bits_of(F a) { return {_mm_castps_si128(a.lo), _mm_castps_si128(a.hi)}; }
inline F float_of(I a) { return {_mm_castsi128_ps(a.lo), _mm_castsi128_ps(a.hi)}; }
inline I greater(F a, F b) {
  return {_mm_castps_si128(_mm_cmpgt_ps(a.lo, b.lo)), _mm_castps_si128(_mm_cmpgt_ps(a.hi, b.hi))};
}
inline F load(const float* p) { return {_mm_loadu_ps(p), _mm_loadu_ps(p + 4)}; }
inline I load(const uint32_t* p) {
  return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 4))};
}
inline __m128i select(__m128i m, __m128i a, __m128i b) { return _mm_or_si128(_mm_and_si128(m, a), _mm_andnot_si128(m, b)); }
inline void store(float* p, F v, I mask, unsigned) {
  const __m128i lo = select(mask.lo, _mm_castps_si128(v.lo), _mm_castps_si128(_mm_loadu_ps(p)));
  const __m128i hi = select(mask.hi, _mm_castps_si128(v.hi), _mm_castps_si128(_mm_loadu_ps(p + 4)));
  _mm_storeu_ps(p, _mm_castsi128_ps(lo));
  _mm_storeu_ps(p + 4, _mm_castsi128_ps(hi));
}
inline void store(uint32_t* p, I v, I mask, unsigned) {
  __m128i* q = reinterpret_cast<__m128i*>(p);
  _mm_storeu_si128(q, select(mask.lo, v.lo, _mm_loadu_si128(q)));
  _mm_storeu_si128(q + 1, select(mask.hi, v.hi, _mm_loadu_si128(q + 1)));
}

#endif

// Depth in [0, 1] rounded to 24-bit unorm (steps of 2^-24) and to a 24-bit
// float (the float's last 7 mantissa bits rounded off, ties up).
inline F quantize_unorm24(F z) { return to_float(round_to_int(z * fset1(16777216.0f))) * fset1(1.0f / 16777216.0f); }
inline F quantize_float24(F z) { return float_of((bits_of(z) + iset1(0x40)) & iset1(int32_t(0xFFFFFF80u))); }

// All ones in the lanes whose bit is set in `m` (8 bits).
inline I from_bits(unsigned m) {
  const I bit = bit_values();
  return (iset1(int32_t(m)) & bit) == bit;
}

}  // namespace cr::span8

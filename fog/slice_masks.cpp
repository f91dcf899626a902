#include "fog/slice_masks.h"

#include <algorithm>

#include <immintrin.h>

#include "fog/sun_term_format.h"

namespace cr {

namespace {

// Bit b of the result: whether h[b] == value, for b < count (<= 64).
template <class V>
uint64_t equal_bits_scalar(const V* h, int count, V value) {
  uint64_t bits = 0;
  for (int b = 0; b < count; ++b) bits |= uint64_t(h[b] == value) << b;
  return bits;
}

__attribute__((target("avx2"))) uint64_t equal_bits_avx2(const float* h, int count, float value) {
  const __m256 v = _mm256_set1_ps(value);
  uint64_t bits = 0;
  int b = 0;
  for (; b + 8 <= count; b += 8)
    bits |= uint64_t(unsigned(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(h + b), v, _CMP_EQ_OQ)))) << b;
  for (; b < count; ++b) bits |= uint64_t(h[b] == value) << b;
  return bits;
}

// The same for 16-bit codes, 32 at a time: two 16-lane compares packed to
// bytes (packs interleaves the halves of its two inputs; the permute puts
// them back in order) and one byte movemask.
__attribute__((target("avx2"))) uint64_t equal_bits_avx2(const uint16_t* h, int count, uint16_t value) {
  const __m256i v = _mm256_set1_epi16(int16_t(value));
  uint64_t bits = 0;
  int b = 0;
  for (; b + 32 <= count; b += 32) {
    const __m256i lo = _mm256_cmpeq_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(h + b)), v);
    const __m256i hi = _mm256_cmpeq_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(h + b + 16)), v);
    const __m256i bytes = _mm256_permute4x64_epi64(_mm256_packs_epi16(lo, hi), _MM_SHUFFLE(3, 1, 2, 0));
    bits |= uint64_t(uint32_t(_mm256_movemask_epi8(bytes))) << b;
  }
  for (; b < count; ++b) bits |= uint64_t(h[b] == value) << b;
  return bits;
}

template <class V>
void masks_of(const V* values, int lit, int words, V zero, V one, uint64_t* out) {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  uint64_t (*equal_bits)(const V*, int, V) = equal_bits_scalar<V>;
  if (avx2) equal_bits = equal_bits_avx2;
  for (int w = 0; w < words; ++w) {
    const int count = lit_in_word(lit, w);
    const uint64_t free = ~low_bits(count);
    out[w] = equal_bits(values + 64 * w, count, zero) | free;
    out[words + w] = equal_bits(values + 64 * w, count, one) | free;
  }
}

}  // namespace

void zero_one_masks(const float* values, int lit, int words, uint64_t* out) {
  masks_of(values, lit, words, FloatSunTerm::kZero, FloatSunTerm::kOne, out);
}

void zero_one_masks(const uint16_t* codes, int lit, int words, uint64_t* out) {
  masks_of(codes, lit, words, Q15SunTerm::kZero, Q15SunTerm::kOne, out);
}

void and_rows(const uint64_t* masks, int nx, int ny, int y, int words, uint64_t* vertical) {
  const size_t per_column = 2 * size_t(words);
  const int ya = std::max(y - 1, 0), yb = std::min(y + 1, ny - 1);
  for (int x = 0; x < nx; ++x) {
    const uint64_t* a = masks + (size_t(ya) * nx + x) * per_column;
    const uint64_t* b = masks + (size_t(y) * nx + x) * per_column;
    const uint64_t* c = masks + (size_t(yb) * nx + x) * per_column;
    uint64_t* v = vertical + size_t(x) * per_column;
    for (size_t i = 0; i < per_column; ++i) v[i] = a[i] & b[i] & c[i];
  }
}

}  // namespace cr

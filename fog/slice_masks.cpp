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

}  // namespace

void zero_one_masks(const float* values, int lit, int words, uint64_t* out) {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  const auto equal_bits = avx2 ? equal_bits_avx2 : equal_bits_scalar<float>;
  for (int w = 0; w < words; ++w) {
    const int count = lit_in_word(lit, w);
    const uint64_t free = ~low_bits(count);
    out[w] = equal_bits(values + 64 * w, count, 0.0f) | free;
    out[words + w] = equal_bits(values + 64 * w, count, 1.0f) | free;
  }
}

void zero_one_masks(const uint16_t* codes, int lit, int words, uint64_t* out) {
  for (int w = 0; w < words; ++w) {
    const int count = lit_in_word(lit, w);
    const uint64_t free = ~low_bits(count);
    out[w] = equal_bits_scalar(codes + 64 * w, count, Q15SunTerm::kZero) | free;
    out[words + w] = equal_bits_scalar(codes + 64 * w, count, Q15SunTerm::kOne) | free;
  }
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

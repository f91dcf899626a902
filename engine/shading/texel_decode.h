#pragma once
// Decoding of an image's RGBA8 texels (as stored in the file) to linear RGBA,
// done as they are sampled; filtering follows on the decoded values, as GPUs
// do. The colour channels of an sRGB image go through the sRGB table
// (srgb_decode_table), every other channel (a linear image's colour, every
// alpha) is code / 255 (unorm_decode_table). One decoder per colour space,
// chosen once per lookup, so the per-texel code has no branch.
#include <array>
#include <cstdint>
#include <cstring>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

#include "engine/core/srgb.h"

namespace cr {

// A texel as four linear floats in one SSE register (R, G, B, A).
typedef float Texel __attribute__((vector_size(16)));

// Value of each 8-bit code of a linear (UNORM) channel: code / 255.
const std::array<float, 256>& unorm_decode_table();

// A linear image's texel: the four channels converted at once and divided by
// 255 (one correctly rounded division per channel, so exactly the table's
// float; tested for every code).
struct LinearTexels {
  [[gnu::always_inline]] Texel operator()(const uint8_t* p) const {
#if defined(__SSE4_1__)
    int32_t bits;
    std::memcpy(&bits, p, sizeof bits);
    return Texel(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(bits)))) / 255.0f;
#else
    return Texel{float(p[0]), float(p[1]), float(p[2]), float(p[3])} / 255.0f;
#endif
  }
#if defined(__AVX2__)
  // Two texels (of two images) side by side, the eight channels at once:
  // the same floats as one at a time.
  typedef float Pair __attribute__((vector_size(32)));
  [[gnu::always_inline]] static Pair pair(const uint8_t* a, const uint8_t* b) {
    int32_t x, y;
    std::memcpy(&x, a, sizeof x);
    std::memcpy(&y, b, sizeof y);
    return Pair(_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_insert_epi32(_mm_cvtsi32_si128(x), y, 1)))) / 255.0f;
  }
#endif
};

// An sRGB image's texel: colour through the sRGB table, alpha linear.
struct SrgbTexels {
  const float* colour = srgb_decode_table().data();
  const float* alpha = unorm_decode_table().data();
  [[gnu::always_inline]] Texel operator()(const uint8_t* p) const {
    return Texel{colour[p[0]], colour[p[1]], colour[p[2]], alpha[p[3]]};
  }
};

}  // namespace cr

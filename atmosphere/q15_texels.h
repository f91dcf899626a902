#pragma once
// The q15 LUT texels' per-pixel arithmetic (engine/core/q15_scale.h): a texel is
// 8 codes in one 16-byte vector (two rgb + pad halves), blended in 16-bit
// integer lanes (fx::lerp_q15: pmulhrsw) and decoded half by half to floats.
#include <cstring>

#include "atmosphere/float4.h"
#include "engine/core/fixed_simd.h"

namespace cr {

inline fx::U16x8 load_q15(const void* p) {
  fx::U16x8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Codes 0-3 and 4-7 decoded (fx::decode_q15) and scaled: the two rgb + pad halves' values.
inline void decode_halves(const fx::U16x8& v, float low_scale, float high_scale, Float4& low, Float4& high) {
  fx::decode_q15(v, low, high);
  low *= low_scale;
  high *= high_scale;
}

inline fx::I16x8 splat_weight(int16_t w) { return fx::I16x8{} + w; }

// Bilinear blend of the texels at a, b (next column), c (next row), d: along x, then y.
inline fx::U16x8 bilinear_q15(const void* a, const void* b, const void* c, const void* d, const fx::I16x8& wx,
                              const fx::I16x8& wy) {
  return fx::lerp_q15(fx::lerp_q15(load_q15(a), load_q15(b), wx), fx::lerp_q15(load_q15(c), load_q15(d), wx), wy);
}

}  // namespace cr

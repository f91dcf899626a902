#pragma once
// Values quantised to 15-bit fixed point (fixed_point.h's q15) with a scale:
// value = decode_q15(code) * scale, the largest value at code 32767. The
// mobile profile's q15 LUTs and specular environment: the bakes stay float
// (they are amortised); when one is complete its values are rounded to the
// grid of a scale chosen for it, so the float consumers (the bakes
// downstream, the lighting) read the same numbers the fixed-point kernels
// decode.
//
// One scale per LUT (and part), not per row or texel: a lerp of two codes is
// then the lerp of their values, and what a pixel shows of an error of half a
// code is half a code of the LUT's brightest texel: below the 8-bit output's
// step wherever the LUT's brightest texel is on screen. Transmittance is in
// [0, 1] and takes scale 1 (so T = 1 is code 32767, 1 - 2^-15).
#include <cstddef>
#include <cstdint>

#include "engine/core/fixed_point.h"

namespace cr {

struct Q15Scale {
  float scale = 1.0f;      // the value of code 32768: value = fx::decode_q15(code) * scale
  float inv_scale = 1.0f;
  float code_value() const { return scale / 32768.0f; }  // the value of one code
};

// The scale that puts `max_value` (>= 0, finite) at code 32767; 1 for an all-zero LUT.
Q15Scale q15_scale_for(float max_value);
uint16_t to_q15(float value, const Q15Scale& s);
inline float from_q15(uint16_t code, const Q15Scale& s) { return fx::decode_q15(code) * s.scale; }
// Largest finite value of `n` floats read with `stride` (0 if none is positive).
float max_value(const float* values, size_t n, size_t stride);
// Rounds `n` floats read with `stride` to the grid in place: v = from_q15(to_q15(v)).
void round_to_q15(float* values, size_t n, size_t stride, const Q15Scale& s);

}  // namespace cr

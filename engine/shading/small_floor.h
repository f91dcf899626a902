#pragma once
// floor() for the texel and LOD coordinates of the inner shading loops.
// std::floor also handles huge values and NaN (and without SSE4.1 expands
// into a long sequence); these coordinates are known to be finite and small,
// where a truncation and one compare give the same value.

namespace cr {

// floor(x) as an int, for finite x with |x| < 2^31. Equals int(std::floor(x)).
inline int floor_to_int(float x) {
  const int i = int(x);
  return float(i) > x ? i - 1 : i;
}

}  // namespace cr

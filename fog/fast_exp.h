#pragma once
// exp(x) for the fog's per-froxel and per-pixel optical depths without a
// libm call: Cody-Waite reduction x = n ln2 + r and the Cephes expf minimax
// polynomial on |r| <= ln2/2 (relative error about 2e-7, like expf).
// Branch-free and libm-free so the compiler can vectorise loops over slices;
// plain float operations, so results are the same on every thread and run.
#include <algorithm>
#include <bit>
#include <cstdint>

namespace cr {

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

}  // namespace cr

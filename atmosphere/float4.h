#pragma once
// Four floats in one SSE register (GCC/Clang vector extension) for RGB math:
// a texel stored as rgb + pad is one 16-byte load, and each lerp is one vector
// operation per step. Lane-wise IEEE arithmetic: every lane is rounded exactly
// as the scalar glm code it replaces, so results are bit-identical.
#include <cstring>

#include <glm/glm.hpp>

namespace cr {

using Float4 = float __attribute__((vector_size(16)));

inline Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline Float4 splat4(float x) { return Float4{x, x, x, x}; }
inline Float4 max4(const Float4& a, const Float4& b) { return a > b ? a : b; }  // lane-wise, as glm::max
inline Float4 to_float4(const glm::vec3& v) { return Float4{v.x, v.y, v.z, 0.0f}; }
inline glm::vec3 to_vec3(const Float4& v) { return glm::vec3(v[0], v[1], v[2]); }

// Bilinear sample of an rgb+pad image (4 floats per texel, `width` texels a
// row) between columns x0, x1 with weight wx and rows y0, y1 with weight wy:
// the same operations, in the same order, as sample_bilinear() of lut_image.h.
inline Float4 bilinear4(const float* texels, int width, int x0, int x1, float wx, int y0, int y1, float wy) {
  const float* row0 = texels + 4 * size_t(y0) * size_t(width);
  const float* row1 = texels + 4 * size_t(y1) * size_t(width);
  const Float4 a0 = load4(row0 + 4 * x0), a1 = load4(row0 + 4 * x1);
  const Float4 b0 = load4(row1 + 4 * x0), b1 = load4(row1 + 4 * x1);
  const Float4 w = splat4(wx);
  const Float4 a = a0 + (a1 - a0) * w;
  const Float4 b = b0 + (b1 - b0) * w;
  return a + (b - a) * splat4(wy);
}

}  // namespace cr

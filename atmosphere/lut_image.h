#pragma once
// An RGB float image (2D or 3D) holding one LUT, with clamped bilinear
// sampling in texel coordinates: texel i covers the unit coordinate i/(n-1),
// so both ends of a parameter range land exactly on texel centres.
#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

struct LutImage {
  int width = 0;
  int height = 0;
  int depth = 1;
  std::vector<glm::vec3> texels;  // x fastest, then y, then z

  LutImage() = default;
  LutImage(int w, int h, int d = 1) : width(w), height(h), depth(d), texels(size_t(w) * h * d, glm::vec3(0.0f)) {}
  size_t count() const { return texels.size(); }
  size_t index(int x, int y, int z = 0) const { return (size_t(z) * height + y) * width + x; }
  glm::vec3& at(int x, int y, int z = 0) { return texels[index(x, y, z)]; }
  const glm::vec3& at(int x, int y, int z = 0) const { return texels[index(x, y, z)]; }
};

// A texel coordinate in [0, n-1] split into a base texel and a weight.
struct LutCoord {
  int i0;
  int i1;
  float w;  // weight of i1
};

inline LutCoord lut_coord(float texel, int n) {
  texel = texel > 0.0f ? std::min(texel, float(n - 1)) : 0.0f;  // NaN -> 0
  const int i0 = std::min(int(texel), n - 1);
  return {i0, std::min(i0 + 1, n - 1), texel - float(i0)};
}

inline glm::vec3 sample_bilinear(const LutImage& img, const LutCoord& x, const LutCoord& y, int z = 0) {
  const glm::vec3* row0 = &img.texels[img.index(0, y.i0, z)];
  const glm::vec3* row1 = &img.texels[img.index(0, y.i1, z)];
  const glm::vec3 a = row0[x.i0] + (row0[x.i1] - row0[x.i0]) * x.w;
  const glm::vec3 b = row1[x.i0] + (row1[x.i1] - row1[x.i0]) * x.w;
  return a + (b - a) * y.w;
}

inline glm::vec3 sample_bilinear(const LutImage& img, float fx, float fy) {
  return sample_bilinear(img, lut_coord(fx, img.width), lut_coord(fy, img.height));
}

}  // namespace cr

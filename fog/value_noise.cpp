#include "fog/value_noise.h"

#include <cmath>
#include <cstdint>

namespace cr {

namespace {

float lattice_value(int32_t x, int32_t y, int32_t z) {
  // A 32-bit integer hash (lowbias32 by Chris Wellons) of the cell.
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u ^ uint32_t(z) * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return float(h >> 8) * (1.0f / 16777216.0f);
}

float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

}  // namespace

float value_noise(const glm::vec3& p) {
  const glm::vec3 f = glm::floor(p);
  const int32_t x = int32_t(f.x), y = int32_t(f.y), z = int32_t(f.z);
  const float u = smooth(p.x - f.x), v = smooth(p.y - f.y), w = smooth(p.z - f.z);
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float x00 = lerp(lattice_value(x, y, z), lattice_value(x + 1, y, z), u);
  const float x10 = lerp(lattice_value(x, y + 1, z), lattice_value(x + 1, y + 1, z), u);
  const float x01 = lerp(lattice_value(x, y, z + 1), lattice_value(x + 1, y, z + 1), u);
  const float x11 = lerp(lattice_value(x, y + 1, z + 1), lattice_value(x + 1, y + 1, z + 1), u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

float fractal_noise(const glm::vec3& p, int octaves) {
  float sum = 0.0f, amplitude = 1.0f, total = 0.0f;
  glm::vec3 q = p;
  for (int i = 0; i < octaves; ++i) {
    sum += amplitude * value_noise(q);
    total += amplitude;
    amplitude *= 0.5f;
    q = q * 2.0f + glm::vec3(17.31f, 5.17f, 11.73f);  // decorrelate octaves
  }
  return sum / total;
}

}  // namespace cr

#include "fog/jitter_sequence.h"

#include <cmath>
#include <cstdint>

namespace cr {

FroxelJitter froxel_jitter(int i) {
  static const float kDepth[kJitterFrames] = {7.0f, 3.0f, 11.0f, 5.0f, 9.0f, 1.0f, 13.0f};
  // Seven hexagonal cells tile one froxel of area 1: cell spacing
  // r = sqrt(2 / (7 sqrt 3)). The six neighbours are visited alternating
  // sides so consecutive frames are far apart.
  static const int kAngleStep[kJitterFrames - 1] = {0, 3, 1, 4, 2, 5};
  const int k = ((i % kJitterFrames) + kJitterFrames) % kJitterFrames;
  FroxelJitter j;
  j.depth = kDepth[k] / 14.0f;
  if (k > 0) {
    const float r = 0.40610f;
    // Rotated by atan(sqrt(3)/5) so the 7-cell super-lattice is axis aligned.
    const float angle = 0.33347f + float(kAngleStep[k - 1]) * 1.04719755f;
    j.lateral = r * glm::vec2(std::cos(angle), std::sin(angle));
  }
  return j;
}

float column_hash(int x, int y) {
  uint32_t h = uint32_t(x) * 0x27d4eb2du ^ (uint32_t(y) + 0x9e3779b9u) * 0x165667b1u;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  h *= 0x297a2d39u;
  h ^= h >> 15;
  return float(h >> 8) * (1.0f / 16777216.0f);
}

}  // namespace cr

#pragma once
// The frame's display transform (exposure, ACES tonemap, sRGB, 8-bit) as a
// table: the per-pixel definition in engine/shading/tonemap.h is a monotone
// step function of the exposed value with 256 steps, so the code of a value
// is found from a bucket index on its float bits plus at most a few
// threshold compares (a fixed number, without branches: a loop until the
// code stopped growing mispredicted where codes change). Results equal resolve_pixel() exactly (tested), at a
// fraction of its cost (no pow/exp per channel).
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

class DisplayTransform {
 public:
  explicit DisplayTransform(float ev100);
  float ev100() const { return ev100_; }
  // 8-bit sRGB code of one channel of linear radiance.
  uint8_t encode(float radiance) const;
  // `count` pixels to packed RGB8.
  void resolve(const glm::vec3* hdr, size_t count, uint8_t* rgb_out) const;

 private:
  float ev100_;
  float exposure_;
  std::array<float, 257> threshold_;  // threshold_[k]: smallest exposed value with code >= k (k = 1..255)
  std::vector<uint8_t> bucket_code_;  // code at the start of each float-bits bucket (non-negative floats)
  int bucket_steps_ = 0;              // most thresholds inside one bucket: the compares encode() makes
};

}  // namespace cr

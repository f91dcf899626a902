#include "engine/render/display_transform.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "engine/core/srgb.h"
#include "engine/shading/tonemap.h"

namespace cr {

namespace {

// The reference definition: one channel of resolve_pixel for an exposed value.
uint8_t code_of_exposed(float e) { return quantize_unorm8(linear_to_srgb(tonemap_aces(e))); }

// Buckets cover exposed values in [2^-24, 2^5) (below: code 0 for any sane
// tonemap, checked at construction; above: the tonemap's shoulder is past 1)
// with 10 mantissa bits each, so a bucket rarely spans more than one code.
constexpr int kBucketShift = 13;
constexpr uint32_t kLowBits = uint32_t(127 - 24) << 23;  // bit pattern of 2^-24
constexpr uint32_t kHighBits = uint32_t(127 + 5) << 23;  // bit pattern of 2^5

}  // namespace

DisplayTransform::DisplayTransform(float ev100) : ev100_(ev100), exposure_(exposure_scale(ev100)) {
  // Thresholds by bisection over the ordered bit patterns of non-negative floats.
  threshold_.fill(std::numeric_limits<float>::infinity());
  threshold_[0] = 0.0f;
  const uint32_t top = std::bit_cast<uint32_t>(std::numeric_limits<float>::max());
  for (int k = 1; k <= 255; ++k) {
    uint32_t lo = 0, hi = top;  // invariant: code(lo) < k <= code(hi) (if any value reaches k)
    if (code_of_exposed(std::bit_cast<float>(hi)) < k) continue;
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      (code_of_exposed(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
    }
    threshold_[k] = std::bit_cast<float>(hi);
  }
  threshold_[256] = std::numeric_limits<float>::infinity();
  bucket_code_.resize(size_t((kHighBits - kLowBits) >> kBucketShift) + 1);
  for (size_t b = 0; b < bucket_code_.size(); ++b) {
    const float start = std::bit_cast<float>(kLowBits + uint32_t(b << kBucketShift));
    int code = 0;
    while (code < 255 && !(start < threshold_[code + 1])) ++code;
    bucket_code_[b] = uint8_t(code);
    // Codes the bucket's values can climb past its start's; the last bucket
    // takes every value above its start.
    const bool last = b + 1 == bucket_code_.size();
    const float end = last ? std::numeric_limits<float>::infinity()
                           : std::bit_cast<float>(kLowBits + uint32_t((b + 1) << kBucketShift));
    int steps = 0;
    while (code + steps < 255 && threshold_[code + steps + 1] < end) ++steps;
    bucket_steps_ = std::max(bucket_steps_, steps);
  }
}

uint8_t DisplayTransform::encode(float radiance) const {
  const float e = radiance * exposure_;
  if (!(e > 0.0f)) return code_of_exposed(e);  // zero, negative and NaN
  if (!(e < std::numeric_limits<float>::infinity())) return code_of_exposed(e);
  const uint32_t bits = std::min(std::max(std::bit_cast<uint32_t>(e), kLowBits), kHighBits);
  int code = bucket_code_[(bits - kLowBits) >> kBucketShift];
  // threshold_[256] is infinite: the code stops at 255.
  for (int s = 0; s < bucket_steps_; ++s) code += e >= threshold_[code + 1] ? 1 : 0;
  return uint8_t(code);
}

void DisplayTransform::resolve(const glm::vec3* hdr, size_t count, uint8_t* rgb_out) const {
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) rgb_out[3 * i + c] = encode(hdr[i][c]);
}

}  // namespace cr

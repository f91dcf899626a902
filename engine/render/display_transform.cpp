#include "engine/render/display_transform.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>

#include "engine/core/hdr16.h"
#include "engine/core/srgb.h"
#include "engine/shading/tonemap.h"

namespace cr {

namespace {

// The reference definition: one channel of resolve_pixel for an exposed value.
uint8_t code_of_exposed(float e) { return quantize_unorm8(linear_to_srgb(tonemap_aces(e))); }

// Buckets of 2^16 floats (7 mantissa bits): each holds at most one of the
// codes' thresholds (checked at construction; at 2^18 some hold two), and the
// ~1700 buckets between code 1 and code 255 take 7 KB, so the table stays in L1.
constexpr int kBucketShift = 16;
constexpr int32_t kBucketWidth = int32_t(1) << kBucketShift;
constexpr int32_t kInfinityBits = 0x7f800000;

// Code of exposed float bits, with the bucket table `bucket` starting at
// `low_bits`. Negative floats (also -NaN) are negative as int32 and clamp to
// code 0; +NaN's bits lie above +infinity's and are sent to 0 as well, like
// the definition does.
inline int code_of_bits(int32_t bits, int32_t low_bits, int32_t high_bits, const uint32_t* bucket) {
  bits = bits > kInfinityBits ? 0 : bits;
  const int32_t offset = std::min(std::max(bits, low_bits), high_bits) - low_bits;
  const uint32_t entry = bucket[offset >> kBucketShift];
  const int32_t step_at = int32_t(entry & 0xffffff);
  return int(entry >> 24) + ((offset & (kBucketWidth - 1)) >= step_at ? 1 : 0);
}

// encode() of `n` floats. The restrict parameters tell GCC that the byte
// stores alias neither the input nor the table, so the loop vectorises.
void encode_floats(const float* __restrict radiance, size_t n, float exposure, int32_t low_bits, int32_t high_bits,
                   const uint32_t* __restrict bucket, uint8_t* __restrict out) {
  for (size_t i = 0; i < n; ++i)
    out[i] = uint8_t(code_of_bits(std::bit_cast<int32_t>(radiance[i] * exposure), low_bits, high_bits, bucket));
}

}  // namespace

DisplayTransform::DisplayTransform(float ev100) : ev100_(ev100), exposure_(exposure_scale(ev100)) {
  // Thresholds by bisection over the ordered bit patterns of non-negative
  // floats: threshold[k] = bits of the smallest exposed value with code >= k.
  std::vector<int32_t> threshold(256);
  const int32_t top = std::bit_cast<int32_t>(std::numeric_limits<float>::max());
  if (code_of_exposed(std::bit_cast<float>(top)) != 255) throw std::logic_error("display transform never reaches 255");
  for (int k = 1; k <= 255; ++k) {
    int32_t lo = 0, hi = top;  // invariant: code(lo) < k <= code(hi)
    while (hi - lo > 1) {
      const int32_t mid = lo + (hi - lo) / 2;
      (code_of_exposed(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
    }
    threshold[k] = hi;
  }
  // The first bucket starts below threshold 1 so that clamped values get 0.
  low_bits_ = ((threshold[1] - 1) >> kBucketShift) << kBucketShift;
  high_bits_ = threshold[255];
  bucket_.resize(size_t((high_bits_ - low_bits_) >> kBucketShift) + 1);
  int code = 0;
  for (size_t b = 0; b < bucket_.size(); ++b) {
    const int32_t start = low_bits_ + int32_t(b) * kBucketWidth;
    while (code < 255 && threshold[code + 1] <= start) ++code;
    int32_t step_at = kBucketWidth;
    if (code < 255 && threshold[code + 1] < start + kBucketWidth) {
      step_at = threshold[code + 1] - start;
      if (code + 1 < 255 && threshold[code + 2] < start + kBucketWidth)
        throw std::logic_error("display transform: two code steps in one bucket; lower kBucketShift");
    }
    bucket_[b] = uint32_t(code) << 24 | uint32_t(step_at);
  }
}

uint8_t DisplayTransform::encode(float radiance) const {
  return uint8_t(code_of_bits(std::bit_cast<int32_t>(radiance * exposure_), low_bits_, high_bits_, bucket_.data()));
}

void DisplayTransform::resolve(const glm::vec3* hdr, size_t count, uint8_t* rgb_out) const {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  encode_floats(reinterpret_cast<const float*>(hdr), 3 * count, exposure_, low_bits_, high_bits_, bucket_.data(), rgb_out);
}

Hdr16Display::Hdr16Display(const DisplayTransform& display) : ev100_(display.ev100()), table_(65536) {
  for (uint32_t code = 0; code < 65536; ++code) table_[code] = display.encode(fx::decode_hdr16(uint16_t(code)));
}

uint8_t Hdr16Display::encode(float radiance) const { return uint8_t(table_[fx::encode_hdr16(radiance)]); }

// The codes of a chunk in one loop that vectorises, then the table reads in
// another (as gathers; in one loop GCC 12 vectorises neither).
void Hdr16Display::resolve(const glm::vec3* hdr, size_t count, uint8_t* rgb_out) const {
  const float* radiance = reinterpret_cast<const float*>(hdr);
  const uint32_t* __restrict table = table_.data();
  constexpr size_t kChunk = 256;
  int32_t codes[kChunk];  // 32-bit indices: the table reads vectorise as gathers
  for (size_t start = 0; start < 3 * count; start += kChunk) {
    const size_t m = std::min(kChunk, 3 * count - start);
    const float* __restrict in = radiance + start;
    uint8_t* __restrict out = rgb_out + start;
    for (size_t i = 0; i < m; ++i) codes[i] = fx::encode_hdr16(in[i]);
    for (size_t i = 0; i < m; ++i) out[i] = uint8_t(table[codes[i]]);
  }
}

}  // namespace cr

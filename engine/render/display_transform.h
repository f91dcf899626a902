#pragma once
// The frame's display transform (exposure, ACES tonemap, sRGB, 8-bit) as a
// table: the per-pixel definition in engine/shading/tonemap.h is a (nearly) monotone
// step function of the exposed value with 256 steps, so the code of a value
// is found from a bucket index on its float bits and one threshold compare
// inside the bucket (buckets are fine enough to hold at most one step;
// checked at construction). Branch-free integer work on the bits, so
// resolve() vectorises (only the bucket loads are per lane). Results equal
// resolve_pixel() (tested), at a fraction of its cost (no pow/exp per
// channel), except at ~160 exposed values within 45 floats of a step, where
// the float evaluation of the definition is itself not monotone: the table
// steps once, at the smallest value that bisection finds.
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
  // Exposed values' bits are clamped to [low_bits_, high_bits_]: every value
  // below low_bits_ has code 0 and every value from high_bits_ up code 255.
  int32_t low_bits_ = 0;
  int32_t high_bits_ = 0;
  // Per bucket of bits above low_bits_: its start's code << 24 | the offset
  // from its start at which the code grows by one (the bucket width if never).
  std::vector<uint32_t> bucket_;
};

// The fixed-point resolve (profile "precision": {"resolve": "fixed"}): each
// channel's radiance becomes its 16-bit HDR code (engine/core/hdr16.h:
// integer operations on the float's bits, relative error <= 2^-11) and the
// code indexes one table of 65536 8-bit codes, DisplayTransform::encode of
// every code's value (exposure included). Codes differ from the float
// resolve only for values within 2^-11 of a step of the display transform.
class Hdr16Display {
 public:
  explicit Hdr16Display(const DisplayTransform& display);
  float ev100() const { return ev100_; }
  uint8_t encode(float radiance) const;
  void resolve(const glm::vec3* hdr, size_t count, uint8_t* rgb_out) const;

 private:
  float ev100_;
  std::vector<uint32_t> table_;  // per hdr16 code: its 8-bit code (32-bit entries: one vector gather reads 8 or 16)
};

}  // namespace cr

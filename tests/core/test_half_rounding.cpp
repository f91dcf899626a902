// round_to_half against the reference: the nearest half by exhaustive search
// over the halves (every one of the 63488 finite non-negative halves decoded
// by its definition), and against F16C where the build has it.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#if defined(__F16C__)
#include <immintrin.h>
#endif

#include "engine/core/half_rounding.h"

namespace {

// A non-negative half's value from its 15 bits, by the definition.
double half_value(uint32_t h) {
  const int e = int(h >> 10), m = int(h & 0x3FF);
  return e == 0 ? std::ldexp(double(m), -24) : std::ldexp(1.0 + double(m) / 1024.0, e - 15);
}

}  // namespace

TEST_CASE("round_to_half: the nearest half (ties to even), saturating at 65504, NaN kept") {
  std::vector<double> halves;
  for (uint32_t h = 0; h < 0x7C00; ++h) halves.push_back(half_value(h));
  // Every half is a fixed point, and the midpoints between neighbours round to the even one.
  for (size_t k = 0; k < halves.size(); ++k) {
    CHECK(double(cr::round_to_half(float(halves[k]))) == halves[k]);
    CHECK(double(cr::round_to_half(-float(halves[k]))) == -halves[k]);
    if (k + 1 < halves.size()) {
      const float mid = float(0.5 * (halves[k] + halves[k + 1]));
      const double expect = (k % 2 == 0) ? halves[k] : halves[k + 1];
      CHECK(double(cr::round_to_half(mid)) == expect);
      CHECK(double(cr::round_to_half(std::nextafter(mid, 0.0f))) == halves[k]);
      CHECK(double(cr::round_to_half(std::nextafter(mid, 1e9f))) == halves[k + 1]);
    }
  }
  CHECK(cr::round_to_half(1e6f) == 65504.0f);
  CHECK(cr::round_to_half(-std::numeric_limits<float>::infinity()) == -65504.0f);
  CHECK(std::isnan(cr::round_to_half(std::numeric_limits<float>::quiet_NaN())));
#if defined(__F16C__)
  // Every 997th float bit pattern, against the hardware conversion (which gives inf past 65504).
  int differing = 0;
  for (uint64_t bits = 0; bits <= 0xFFFFFFFFu; bits += 997) {
    const float x = std::bit_cast<float>(uint32_t(bits));
    if (std::isnan(x) || std::abs(x) > 65504.0f) continue;
    const float hw = _cvtsh_ss(_cvtss_sh(x, _MM_FROUND_TO_NEAREST_INT));
    differing += std::bit_cast<uint32_t>(hw) != std::bit_cast<uint32_t>(cr::round_to_half(x)) ? 1 : 0;
  }
  CHECK(differing == 0);
#endif
}

// hdr16 (engine/core/hdr16.h) exhaustively over its 65536 codes and at every
// rounding boundary, and over a dense sweep of floats: exact decode, round
// trip, monotone codes, nearest code with ties to even, the 2^-11 relative
// error bound, saturation, NaN, infinities and negatives.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <doctest/doctest.h>

#include "engine/core/hdr16.h"

using namespace cr::fx;

namespace {

// The format's definition, independently: E = 0 is m * 2^-40, else
// (1024 + m) * 2^(E - 41).
double hdr16_value(uint32_t c) {
  const int e = int(c >> 10), m = int(c & 1023);
  return e == 0 ? std::ldexp(m, -40) : std::ldexp(1024 + m, e - 41);
}

}  // namespace

TEST_CASE("hdr16: every code decodes exactly, round-trips, and codes are strictly monotone") {
  CHECK(decode_hdr16(0) == 0.0f);
  CHECK(decode_hdr16(1) == kHdr16MinDenormal);
  CHECK(decode_hdr16(0x400) == kHdr16MinNormal);
  CHECK(decode_hdr16(0xFFFF) == kHdr16Max);
  CHECK(decode_hdr16(31 << 10) == 1.0f);
  for (uint32_t c = 0; c < 65536; ++c) {
    const float x = decode_hdr16(uint16_t(c));
    if (double(x) != hdr16_value(c) || encode_hdr16(x) != c) FAIL("code " << c);
    if (c > 0 && !(x > decode_hdr16(uint16_t(c - 1)))) FAIL("not increasing at " << c);
  }
}

TEST_CASE("hdr16: floats either side of every midpoint go to the nearer code, a midpoint to the even one") {
  for (uint32_t c = 0; c < 65535; ++c) {
    // 11 significant bits a code, so the midpoint (12 bits) is a float.
    const double mid_d = (hdr16_value(c) + hdr16_value(c + 1)) / 2;
    const float mid = float(mid_d);
    REQUIRE(double(mid) == mid_d);
    const uint32_t even = (c & 1) ? c + 1 : c;
    if (encode_hdr16(mid) != even || encode_hdr16(std::nextafter(mid, 0.0f)) != c ||
        encode_hdr16(std::nextafter(mid, kHdr16Max)) != c + 1)
      FAIL("code " << c);
  }
}

TEST_CASE("hdr16: saturation at the top, flush below half the smallest denormal, NaN, infinities, negatives") {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  CHECK(encode_hdr16(kHdr16Max) == 0xFFFF);
  CHECK(encode_hdr16(std::nextafter(kHdr16Max, kInf)) == 0xFFFF);
  CHECK(encode_hdr16(0x1p33f) == 0xFFFF);
  CHECK(encode_hdr16(1e20f) == 0xFFFF);
  CHECK(encode_hdr16(std::numeric_limits<float>::max()) == 0xFFFF);
  CHECK(encode_hdr16(kInf) == 0xFFFF);
  CHECK(encode_hdr16(0x1p-41f) == 0);  // a tie between 0 and the smallest denormal
  CHECK(encode_hdr16(std::nextafter(0x1p-41f, 1.0f)) == 1);
  CHECK(encode_hdr16(1e-20f) == 0);
  CHECK(encode_hdr16(std::numeric_limits<float>::min()) == 0);
  CHECK(encode_hdr16(std::numeric_limits<float>::denorm_min()) == 0);
  CHECK(encode_hdr16(0.0f) == 0);
  CHECK(encode_hdr16(-0.0f) == 0);
  CHECK(encode_hdr16(-1.0f) == 0);
  CHECK(encode_hdr16(-kHdr16Max) == 0);
  CHECK(encode_hdr16(-kInf) == 0);
  for (uint32_t nan : {0x7FC00000u, 0x7F800001u, 0x7FFFFFFFu, 0xFFC00000u, 0xFF800001u})
    CHECK(encode_hdr16(std::bit_cast<float>(nan)) == 0);
  // The radiance range it is for, within 2^-11.
  for (float x : {1e-4f, 1e-2f, 1.0f, 1e3f, 1.6e9f})
    CHECK(std::abs(decode_hdr16(encode_hdr16(x)) - x) <= x * 0x1p-11f);
}

TEST_CASE("hdr16: encode is monotone over a dense float sweep, relative error <= 2^-11 on the normal range") {
  uint16_t last = 0;
  double worst_rel = 0.0, worst_denormal = 0.0;
  for (uint64_t b = 0; b <= 0x7F800000u; b += 1021) {
    const float x = std::bit_cast<float>(uint32_t(b));
    const uint16_t c = encode_hdr16(x);
    if (c < last) FAIL("not monotone at " << x);
    last = c;
    const double err = std::abs(double(decode_hdr16(c)) - double(x));
    if (x >= kHdr16MinNormal && x <= kHdr16Max)
      worst_rel = std::max(worst_rel, err / x);
    else if (x < kHdr16MinNormal)
      worst_denormal = std::max(worst_denormal, err);
    else if (c != 0xFFFF)
      FAIL("no saturation at " << x);
  }
  CHECK(last == 0xFFFF);
  CHECK(worst_rel <= 0x1p-11);
  CHECK(worst_denormal <= 0x1p-41);  // half a denormal step
}

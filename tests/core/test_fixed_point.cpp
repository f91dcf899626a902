// The scalar fixed-point definitions (engine/core/fixed_point.h) against
// exact references in double or wide integers: rounding to nearest,
// saturation at both ends, no wrap-around, monotonicity and error bounds,
// exhaustively over 16-bit inputs and densely (fixed-seed random) beyond.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <doctest/doctest.h>

#include "engine/core/fixed_point.h"

using namespace cr::fx;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Every step-th float from lo up to hi (both non-negative), in increasing order.
std::vector<float> float_sweep(float lo, float hi, uint32_t step) {
  std::vector<float> xs;
  for (uint32_t b = std::bit_cast<uint32_t>(lo); b <= std::bit_cast<uint32_t>(hi); b += step)
    xs.push_back(std::bit_cast<float>(b));
  xs.push_back(hi);
  return xs;
}

// Lattice 0, step, 2 step, ... up to hi, plus the given corners.
std::vector<int32_t> lattice(int32_t lo, int32_t hi, int32_t step, std::initializer_list<int32_t> corners) {
  std::vector<int32_t> v(corners);
  for (int32_t i = lo; i <= hi; i += step) v.push_back(i);
  return v;
}

int64_t floor_div(int64_t a, int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

}  // namespace

TEST_CASE("q15 encode: nearest code, ties to even, at every code boundary") {
  for (uint32_t c = 0; c < 32767; ++c) {
    CHECK(encode_q15(decode_q15(uint16_t(c))) == c);
    const float mid = float(2 * c + 1) / 65536.0f;  // exact: 16 significant bits
    const uint32_t even = (c & 1) ? c + 1 : c;
    if (encode_q15(mid) != even || encode_q15(std::nextafter(mid, 0.0f)) != c ||
        encode_q15(std::nextafter(mid, 1.0f)) != c + 1)
      FAIL("code " << c);
  }
  CHECK(encode_q15(decode_q15(32767)) == 32767);
}

TEST_CASE("q15 encode: saturates at 0 and 32767, NaN is 0, error <= 2^-16, monotone") {
  CHECK(encode_q15(0.0f) == 0);
  CHECK(encode_q15(-0.0f) == 0);
  CHECK(encode_q15(-1.0f) == 0);
  CHECK(encode_q15(-kInf) == 0);
  CHECK(encode_q15(kNaN) == 0);
  CHECK(encode_q15(-kNaN) == 0);
  CHECK(encode_q15(std::numeric_limits<float>::denorm_min()) == 0);
  CHECK(encode_q15(32767.0f / 32768.0f) == 32767);
  CHECK(encode_q15(1.0f) == 32767);
  CHECK(encode_q15(2.0f) == 32767);
  CHECK(encode_q15(std::numeric_limits<float>::max()) == 32767);
  CHECK(encode_q15(kInf) == 32767);

  uint16_t last = 0;
  double worst = 0.0;
  for (float x : float_sweep(0.0f, 32767.0f / 32768.0f, 397)) {
    const uint16_t c = encode_q15(x);
    worst = std::max(worst, std::abs(double(decode_q15(c)) - double(x)));
    if (c < last) FAIL("not monotone at " << x);
    last = c;
  }
  CHECK(worst <= 0x1p-16);
  // Decode is exact: c / 32768.
  for (uint32_t c = 0; c < 65536; ++c)
    if (double(decode_q15(uint16_t(c))) != double(c) / 32768.0) FAIL("decode " << c);
}

TEST_CASE("q15 weight: round(w * 32768), 1.0 saturates to 32767, NaN is 0") {
  CHECK(weight_q15(0.0f) == 0);
  CHECK(weight_q15(0.5f) == 16384);
  CHECK(weight_q15(0.25f) == 8192);
  CHECK(weight_q15(1.0f) == 32767);
  CHECK(weight_q15(1.5f) == 32767);
  CHECK(weight_q15(-0.25f) == 0);
  CHECK(weight_q15(kNaN) == 0);
  for (float w : float_sweep(0.0f, 1.0f, 1021))
    if (weight_q15(w) != int16_t(encode_q15(w))) FAIL(w);
}

TEST_CASE("mul_round_q15 is pmulhrsw: (a * b + 2^14) >> 15, exact, only -32768^2 wraps") {
  const std::vector<int32_t> bs = lattice(-32768, 32767, 257, {-32768, -32767, -16384, -1, 0, 1, 16384, 32766, 32767});
  for (int32_t a = -32768; a <= 32767; ++a)
    for (int32_t b : bs) {
      // floor(a * b / 32768 + 1/2), exact in double (|a * b| < 2^31).
      const double exact = std::floor(double(a) * double(b) / 32768.0 + 0.5);
      const int32_t r = mul_round_q15(int16_t(a), int16_t(b));
      if (a == -32768 && b == -32768) {
        CHECK(r == -32768);  // 32768 truncated to 16 bits, as the instruction does
      } else if (double(r) != exact) {
        FAIL(a << " * " << b << " = " << r << ", expected " << exact);
      }
    }
  CHECK(mul_round_q15(32767, 32767) == 32766);
  CHECK(mul_round_q15(-32768, 32767) == -32767);
  CHECK(mul_round_q15(1, 16384) == 1);    // 0.5 rounds up
  CHECK(mul_round_q15(-1, 16384) == 0);   // -0.5 rounds up too
}

TEST_CASE("lerp_q15: between a and b, monotone in w, a at w = 0, within 0.5 code") {
  // Every w for pairs on a lattice with the corners.
  const std::vector<int32_t> ends = lattice(0, 32767, 2047, {1, 2, 16383, 16384, 16385, 32765, 32766, 32767});
  for (int32_t a : ends)
    for (int32_t b : ends) {
      int32_t last = a;
      bool ok = true;
      for (int32_t w = 0; w <= 32767; ++w) {
        const int32_t r = lerp_q15(uint16_t(a), uint16_t(b), int16_t(w));
        const double exact = a + double(b - a) * w / 32768.0;
        ok &= r >= std::min(a, b) && r <= std::max(a, b);
        ok &= b >= a ? r >= last : r <= last;
        ok &= std::abs(r - exact) <= 0.5 && double(r) == std::floor(exact + 0.5);
        last = r;
      }
      ok &= lerp_q15(uint16_t(a), uint16_t(b), 0) == a;
      // At w = 32767: b exactly when -16384 < b - a <= 16384 (half a code
      // rounds up), one code short of b beyond.
      ok &= lerp_q15(uint16_t(a), uint16_t(b), 32767) == (b - a > -16384 && b - a <= 16384 ? b : b - (b > a ? 1 : -1));
      if (!ok) FAIL("a = " << a << ", b = " << b);
    }
  // Every a against a lattice of b at a few weights, random ones included.
  std::mt19937 rng(15);
  std::vector<int32_t> ws = {1, 2, 8192, 16383, 16384, 16385, 32766, 32767};
  for (int i = 0; i < 8; ++i) ws.push_back(int32_t(rng() % 32768));
  const std::vector<int32_t> bs = lattice(0, 32767, 331, {32767});
  for (int32_t a = 0; a <= 32767; ++a)
    for (int32_t b : bs)
      for (int32_t w : ws) {
        const int32_t r = lerp_q15(uint16_t(a), uint16_t(b), int16_t(w));
        if (r < std::min(a, b) || r > std::max(a, b) || double(r) != std::floor(a + double(b - a) * w / 32768.0 + 0.5))
          FAIL("a = " << a << ", b = " << b << ", w = " << w << ": " << r);
      }
}

TEST_CASE("unorm16 encode/decode: nearest code on both sides of every midpoint, saturation, NaN") {
  for (uint32_t c = 0; c < 65535; ++c) {
    // Decode is the float nearest c / 65535: within half a float ulp (< 2^-25).
    if (encode_unorm16(decode_unorm16(uint16_t(c))) != c ||
        std::abs(double(decode_unorm16(uint16_t(c))) - c / 65535.0) > 0x1p-25)
      FAIL("round trip of " << c);
    // (c + 1/2) / 65535 is no float (65535 is odd) except 0.5 itself, a tie
    // that goes to the even code 32768; floats either side round to the side.
    const double mid = (c + 0.5) / 65535.0;
    const float below = float(mid) < mid ? float(mid) : std::nextafter(float(mid), 0.0f);
    const float above = float(mid) > mid ? float(mid) : std::nextafter(float(mid), 1.0f);
    if (encode_unorm16(below) != c || encode_unorm16(above) != c + 1) FAIL("code " << c);
  }
  CHECK(encode_unorm16(0.5f) == 32768);
  CHECK(encode_unorm16(1.0f) == 65535);
  CHECK(encode_unorm16(1.5f) == 65535);
  CHECK(encode_unorm16(kInf) == 65535);
  CHECK(encode_unorm16(-0.5f) == 0);
  CHECK(encode_unorm16(-kInf) == 0);
  CHECK(encode_unorm16(kNaN) == 0);
  CHECK(decode_unorm16(65535) == 1.0f);
  CHECK(decode_unorm16(0) == 0.0f);

  uint16_t last = 0;
  double worst = 0.0;
  for (float x : float_sweep(0.0f, 1.0f, 397)) {
    const uint16_t c = encode_unorm16(x);
    worst = std::max(worst, std::abs(c / 65535.0 - double(x)));
    if (c < last) FAIL("not monotone at " << x);
    last = c;
  }
  CHECK(worst <= 0.5 / 65535.0);
}

TEST_CASE("mul_unorm16 is round(a * b / 65535) exactly, no wrap at the top") {
  CHECK(mul_unorm16(65535, 65535) == 65535);
  CHECK(mul_unorm16(65535, 65534) == 65534);
  CHECK(mul_unorm16(1, 1) == 0);
  CHECK(mul_unorm16(256, 128) == 1);  // 32768 / 65535 = 0.500008 rounds up
  CHECK(mul_unorm16(255, 128) == 0);  // 32640 / 65535 = 0.498 rounds down
  const std::vector<int32_t> bs =
      lattice(0, 65535, 251, {1, 2, 3, 255, 256, 257, 32767, 32768, 32769, 65533, 65534, 65535});
  for (uint32_t a = 0; a <= 65535; ++a) {
    if (mul_unorm16(uint16_t(a), 65535) != a || mul_unorm16(uint16_t(a), 0) != 0) FAIL("identity at " << a);
    for (int32_t b : bs) {
      // Exact: floor((2ab + 65535) / 131070), no ties (65535 is odd).
      const uint64_t exact = (2 * uint64_t(a) * uint64_t(b) + 65535) / 131070;
      if (mul_unorm16(uint16_t(a), uint16_t(b)) != exact) FAIL(a << " * " << b);
    }
  }
}

TEST_CASE("Q1.14: every code round-trips, ties to even, saturation at -2 and 2 - 2^-14, NaN is 0") {
  for (int32_t c = -32768; c <= 32767; ++c) {
    const float x = decode_q1_14(int16_t(c));
    if (double(x) != c / 16384.0 || encode_q1_14(x) != c) FAIL("round trip of " << c);
    if (c < 32767) {
      const float mid = float(2 * c + 1) / 32768.0f;
      const int32_t even = (c & 1) ? c + 1 : c;
      if (encode_q1_14(mid) != even || encode_q1_14(std::nextafter(mid, -3.0f)) != c ||
          encode_q1_14(std::nextafter(mid, 3.0f)) != c + 1)
        FAIL("code " << c);
    }
  }
  CHECK(encode_q1_14(2.0f) == 32767);
  CHECK(encode_q1_14(kInf) == 32767);
  CHECK(encode_q1_14(-2.0f) == -32768);
  CHECK(encode_q1_14(-3.0f) == -32768);
  CHECK(encode_q1_14(-kInf) == -32768);
  CHECK(encode_q1_14(kNaN) == 0);
}

TEST_CASE("Q16.16 encode/decode: nearest, ties to even, saturation, NaN is 0") {
  for (int32_t c = -(1 << 24); c <= (1 << 24); c += 7)  // decode is exact up to 2^24
    if (double(decode_q16_16(c)) != c / 65536.0 || encode_q16_16(decode_q16_16(c)) != c) FAIL("round trip of " << c);
  CHECK(encode_q16_16(0.5f / 65536.0f) == 0);
  CHECK(encode_q16_16(1.5f / 65536.0f) == 2);
  CHECK(encode_q16_16(-1.5f / 65536.0f) == -2);
  CHECK(encode_q16_16(-2.5f / 65536.0f) == -2);
  CHECK(encode_q16_16(32767.0f) == 32767 * 65536);
  CHECK(encode_q16_16(32768.0f) == std::numeric_limits<int32_t>::max());
  CHECK(encode_q16_16(std::nextafter(32768.0f, 0.0f)) == 2147483520);  // 2^31 - 128: exact
  CHECK(encode_q16_16(1e30f) == std::numeric_limits<int32_t>::max());
  CHECK(encode_q16_16(kInf) == std::numeric_limits<int32_t>::max());
  CHECK(encode_q16_16(-32768.0f) == std::numeric_limits<int32_t>::min());
  CHECK(encode_q16_16(-1e30f) == std::numeric_limits<int32_t>::min());
  CHECK(encode_q16_16(-kInf) == std::numeric_limits<int32_t>::min());
  CHECK(encode_q16_16(kNaN) == 0);
  // Decode beyond 2^24 is the nearest float.
  CHECK(decode_q16_16(std::numeric_limits<int32_t>::max()) == 32768.0f);
  CHECK(decode_q16_16((1 << 24) + 1) == 256.0f);
}

TEST_CASE("mul_q16_16: rounded half up, within 0.5 code, saturating instead of wrapping") {
  constexpr int32_t kMin = std::numeric_limits<int32_t>::min(), kMax = std::numeric_limits<int32_t>::max();
  auto reference = [](int32_t a, int32_t b) {
    const int64_t r = floor_div(int64_t(a) * b + 32768, 65536);
    return int32_t(std::clamp<int64_t>(r, kMin, kMax));
  };
  CHECK(mul_q16_16(65536, 12345) == 12345);
  CHECK(mul_q16_16(-65536, 12345) == -12345);
  CHECK(mul_q16_16(1, 32768) == 1);    // 0.5 code rounds up
  CHECK(mul_q16_16(-1, 32768) == 0);   // -0.5 code rounds up
  CHECK(mul_q16_16(-1, 32769) == -1);
  CHECK(mul_q16_16(kMin, kMin) == kMax);
  CHECK(mul_q16_16(kMax, kMax) == kMax);
  CHECK(mul_q16_16(kMin, kMax) == kMin);
  CHECK(mul_q16_16(kMin, -65536) == kMax);  // -(-32768) does not fit: saturates
  CHECK(mul_q16_16(kMin, 65536) == kMin);
  std::mt19937 rng(1616);
  for (int i = 0; i < 1000000; ++i) {
    // Mixed magnitudes: full-range values and values near 1.
    const int32_t a = int32_t(rng()) >> (rng() % 24), b = int32_t(rng()) >> (rng() % 24);
    const int32_t r = mul_q16_16(a, b);
    if (r != reference(a, b)) FAIL(a << " * " << b);
    const double exact = double(a) * double(b) / 65536.0;  // exact: 62-bit product / 2^16
    if (exact > kMin && exact < kMax && std::abs(r - exact) > 0.5) FAIL(a << " * " << b);
  }
}

TEST_CASE("reciprocal_q16_16: exactly rounded 2^32 / x, monotone, saturating for x <= 1") {
  CHECK(reciprocal_q16_16(0) == 0xFFFFFFFFu);
  CHECK(reciprocal_q16_16(1) == 0xFFFFFFFFu);
  CHECK(reciprocal_q16_16(2) == 0x80000000u);
  CHECK(reciprocal_q16_16(65536) == 65536u);           // 1 / 1
  CHECK(reciprocal_q16_16(131072) == 32768u);          // 1 / 2
  CHECK(reciprocal_q16_16(3 * 65536) == 21845u);       // 1 / 3 = 21845.33 codes
  CHECK(reciprocal_q16_16(0xFFFFFFFFu) == 1u);
  // Exactly rounded: |r x - 2^32| <= x / 2, an integer test; and against double.
  auto check = [](uint32_t x) {
    const uint32_t r = reciprocal_q16_16(x);
    const int64_t residual = int64_t(uint64_t(r) * x) - (int64_t(1) << 32);
    const double err = std::abs(double(r) - 4294967296.0 / x);
    return 2 * std::abs(residual) <= int64_t(x) && err <= 0.5;
  };
  uint32_t last = 0xFFFFFFFFu;
  for (uint32_t x = 2; x < (1u << 20); ++x) {
    const uint32_t r = reciprocal_q16_16(x);
    if (!check(x) || r > last) FAIL("x = " << x);
    last = r;
  }
  std::mt19937 rng(32);
  for (int i = 0; i < 1000000; ++i) {
    const uint32_t x = std::max<uint32_t>(2, rng() >> (rng() % 31));
    if (!check(x)) FAIL("x = " << x);
  }
}

TEST_CASE("exp2_neg_q15: within 0.5 + 2^-15 code of 32768 * 2^-x for every x below 17, monotone, 0 beyond 16") {
  uint32_t last = 32767;
  double worst = 0.0;
  for (uint32_t x = 0; x < (17u << 16); ++x) {
    const uint32_t r = exp2_neg_q15(x);
    const double exact = std::min(32767.0, 32768.0 * std::exp2(-double(x) / 65536.0));
    worst = std::max(worst, std::abs(r - exact));
    if (r > last) FAIL("not monotone at x = " << x);
    last = r;
  }
  CHECK(worst <= 0.5 + 0x1p-15);
  CHECK(exp2_neg_q15(0) == 32767);  // 2^0 = 1 saturates
  for (uint32_t n = 1; n <= 15; ++n) CHECK(exp2_neg_q15(n << 16) == (32768u >> n));
  CHECK(exp2_neg_q15(16u << 16) == 1);  // 0.5 code rounds up
  CHECK(exp2_neg_q15((16u << 16) + 1) == 0);
  CHECK(exp2_neg_q15(17u << 16) == 0);
  CHECK(exp2_neg_q15(0xFFFFFFFFu) == 0);
}

TEST_CASE("log2_q16_16: within 0.5 + 2^-12 code of log2(x / 65536), exact at powers of two, monotone") {
  auto error = [](uint32_t x) { return std::abs(log2_q16_16(x) - std::log2(double(x) / 65536.0) * 65536.0); };
  double worst = 0.0;
  int32_t last = log2_q16_16(1);
  for (uint32_t x = 1; x <= (1u << 21); ++x) {  // every 16-bit input and beyond
    const int32_t r = log2_q16_16(x);
    worst = std::max(worst, error(x));
    if (r < last) FAIL("not monotone at x = " << x);
    last = r;
  }
  std::mt19937 rng(2);
  for (int i = 0; i < 1000000; ++i) worst = std::max(worst, error(std::max<uint32_t>(1, rng() >> (rng() % 32))));
  CHECK(worst <= 0.5 + 0x1p-12);
  for (int k = 0; k < 32; ++k) CHECK(log2_q16_16(1u << k) == (k - 16) * 65536);
  CHECK(log2_q16_16(0) == std::numeric_limits<int32_t>::min());
  CHECK(log2_q16_16(0xFFFFFFFFu) == 16 * 65536);  // log2(65536 - 2^-16) rounds to 16
  CHECK(log2_q16_16(3 * 65536) == 103872);         // log2(3) = 1.58496 = 103872.4 / 65536
}

// The vector forms (engine/core/fixed_simd.h) against the scalar definitions
// (engine/core/fixed_point.h), lane by lane and bit for bit: exhaustive
// sub-lattices of (a, b, w), every q15 code and rounding boundary, special
// floats, and random inputs with fixed seeds.
#include <algorithm>
#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <doctest/doctest.h>

#include "engine/core/fixed_point.h"
#include "engine/core/fixed_simd.h"

namespace fx = cr::fx;

namespace {

// Lattice lo, lo + step, ... up to hi, plus the corners.
std::vector<int32_t> simd_lattice(int32_t lo, int32_t hi, int32_t step, std::initializer_list<int32_t> corners) {
  std::vector<int32_t> v(corners);
  for (int32_t i = lo; i <= hi; i += step) v.push_back(i);
  return v;
}

// Lanes of mul_round_q15 and lerp_q15 (8 or 16 at once) against the scalar
// for the operand triples (a[i], b[i], w[i]), the last vector zero-padded;
// returns the mismatches.
template <class U, class I>
int check_lanes(const std::vector<int32_t>& a, const std::vector<int32_t>& b, const std::vector<int32_t>& w) {
  constexpr size_t n = sizeof(U) / sizeof(uint16_t);
  int bad = 0;
  for (size_t k = 0; k < a.size(); k += n) {
    U ua{}, ub{};
    I ia{}, iw{};
    for (size_t i = 0; i < n && k + i < a.size(); ++i) {
      ua[i] = uint16_t(a[k + i]);
      ub[i] = uint16_t(b[k + i]);
      ia[i] = int16_t(a[k + i]);
      iw[i] = int16_t(w[k + i]);
    }
    const I m = cr::fx::mul_round_q15(ia, iw);
    const U l = cr::fx::lerp_q15(ua, ub, iw);
    for (size_t i = 0; i < n; ++i) {
      bad += m[i] != cr::fx::mul_round_q15(ia[i], iw[i]);
      bad += l[i] != cr::fx::lerp_q15(ua[i], ub[i], iw[i]);
    }
  }
  return bad;
}

// Every width the baseline has; returns the mismatches.
int check_lanes(const std::vector<int32_t>& a, const std::vector<int32_t>& b, const std::vector<int32_t>& w) {
  int bad = check_lanes<fx::U16x8, fx::I16x8>(a, b, w);
#if defined(__AVX2__)
  bad += check_lanes<fx::U16x16, fx::I16x16>(a, b, w);
#endif
  return bad;
}

// encode_q15 of eight floats at a time (as two F32x4 and, with AVX2, as one
// F32x8) against the scalar, and decode_q15 of the codes; the mismatches.
int check_encode(const std::vector<float>& xs) {
  int bad = 0;
  auto compare = [&](const float* x, fx::U16x8 c, const void* decoded) {
    float d[8];
    std::memcpy(d, decoded, sizeof d);
    for (size_t i = 0; i < 8; ++i) {
      bad += c[i] != fx::encode_q15(x[i]);
      bad += std::bit_cast<uint32_t>(d[i]) != std::bit_cast<uint32_t>(fx::decode_q15(c[i]));
    }
  };
  for (size_t k = 0; k + 8 <= xs.size(); k += 8) {
    fx::F32x4 lo, hi, d[2];
    std::memcpy(&lo, &xs[k], sizeof lo);
    std::memcpy(&hi, &xs[k + 4], sizeof hi);
    const fx::U16x8 c = fx::encode_q15(lo, hi);
    fx::decode_q15(c, d[0], d[1]);
    compare(&xs[k], c, d);
#if defined(__AVX2__)
    fx::F32x8 x8;
    std::memcpy(&x8, &xs[k], sizeof x8);
    const fx::U16x8 c8 = fx::encode_q15(x8);
    const fx::F32x8 d8 = fx::decode_q15(c8);
    compare(&xs[k], c8, &d8);
#endif
  }
  return bad;
}

}  // namespace

TEST_CASE("simd lerp_q15 and mul_round_q15, 8 and 16 lanes: every w for (a, b) on a lattice") {
  const std::vector<int32_t> ends = simd_lattice(0, 32767, 4095, {1, 2, 16383, 16384, 16385, 32765, 32766, 32767});
  std::vector<int32_t> every_w(32768), a(32768), b(32768);
  for (int32_t w = 0; w <= 32767; ++w) every_w[w] = w;
  int bad = 0;
  for (int32_t ea : ends)
    for (int32_t eb : ends) {
      std::fill(a.begin(), a.end(), ea);
      std::fill(b.begin(), b.end(), eb);
      bad += check_lanes(a, b, every_w);
    }
  CHECK(bad == 0);
}

TEST_CASE("simd lerp_q15: every a against a lattice of b and w") {
  std::vector<int32_t> b, w;
  for (int32_t eb : simd_lattice(0, 32767, 2039, {32767}))
    for (int32_t ew : simd_lattice(0, 32767, 4093, {1, 16384, 32767})) {
      b.push_back(eb);
      w.push_back(ew);
    }
  int bad = 0;
  for (int32_t a = 0; a <= 32767; ++a) bad += check_lanes(std::vector<int32_t>(b.size(), a), b, w);
  CHECK(bad == 0);
}

TEST_CASE("simd mul_round_q15 over the whole int16 range, and lerp_q15 on random inputs") {
  // Every a against a lattice of b, the -32768 * -32768 wrap included
  // (lerp_q15 gets them too: outside 0..32767 both wrap the same way).
  const std::vector<int32_t> b = simd_lattice(-32768, 32767, 1021, {-32768, -32767, -1, 0, 1, 32767});
  int bad = 0;
  for (int32_t a = -32768; a <= 32767; ++a) bad += check_lanes(std::vector<int32_t>(b.size(), a), b, b);
  CHECK(bad == 0);

  std::mt19937 rng(8);
  std::vector<int32_t> ra(1 << 20), rb(1 << 20), rw(1 << 20);
  for (size_t i = 0; i < ra.size(); ++i) {
    ra[i] = int32_t(rng() % 32768);
    rb[i] = int32_t(rng() % 32768);
    rw[i] = int32_t(rng() % 32768);
  }
  CHECK(check_lanes(ra, rb, rw) == 0);
}

TEST_CASE("simd encode_q15 and decode_q15 of 8 floats: every code, every midpoint and its neighbours, specials") {
  std::vector<float> xs;
  for (uint32_t c = 0; c < 32768; ++c) {
    const float mid = float(2 * c + 1) / 65536.0f;
    xs.insert(xs.end(), {fx::decode_q15(uint16_t(c)), mid, std::nextafter(mid, 0.0f), std::nextafter(mid, 2.0f)});
  }
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (float s : {0.0f, -0.0f, -1e-30f, -0.5f, -1.0f, -kInf, 1.0f, 1.5f, 1e30f, kInf, std::numeric_limits<float>::max(),
                  std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                  std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                  std::bit_cast<float>(0x7F800001u), std::bit_cast<float>(0xFFFFFFFFu)})
    xs.insert(xs.end(), 8, s);  // alone in a vector, and next to others
  xs.insert(xs.end(), {std::numeric_limits<float>::quiet_NaN(), 0.25f, kInf, -kInf, 0.75f, -0.0f, 2.0f, 1e-6f});
  xs.resize(xs.size() / 8 * 8);
  CHECK(check_encode(xs) == 0);
}

TEST_CASE("simd encode_q15 of 8 floats rounds in the current mode as the scalar does, under every mode") {
  std::vector<float> xs;
  for (uint32_t c = 0; c < 32768; c += 3) {
    const float mid = float(2 * c + 1) / 65536.0f;
    xs.insert(xs.end(), {mid, std::nextafter(mid, 0.0f), std::nextafter(mid, 2.0f), fx::decode_q15(uint16_t(c))});
  }
  for (int mode : {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO}) {
    std::fesetround(mode);
    const int bad = check_encode(xs);
    std::fesetround(FE_TONEAREST);
    CHECK_MESSAGE(bad == 0, "mode " << mode);
  }
}

TEST_CASE("simd encode_q15 of 8 floats: a dense sweep of [0, 1.25] and random bit patterns") {
  std::vector<float> xs;
  for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(1.25f); bits += 613) xs.push_back(std::bit_cast<float>(bits));
  std::mt19937 rng(16);
  for (int i = 0; i < (1 << 20); ++i) xs.push_back(std::bit_cast<float>(uint32_t(rng())));  // NaNs, negatives, huge
  xs.resize(xs.size() / 8 * 8);
  CHECK(check_encode(xs) == 0);
}

TEST_CASE("simd decode_q15: every 16-bit code, bit for bit") {
  int bad = 0;
  auto compare = [&](uint32_t c0, const void* decoded) {
    float d[8];
    std::memcpy(d, decoded, sizeof d);
    for (uint32_t i = 0; i < 8; ++i)
      bad += std::bit_cast<uint32_t>(d[i]) != std::bit_cast<uint32_t>(fx::decode_q15(uint16_t(c0 + i)));
  };
  for (uint32_t c = 0; c < 65536; c += 8) {
    fx::U16x8 v;
    for (uint32_t i = 0; i < 8; ++i) v[i] = uint16_t(c + i);
    fx::F32x4 d[2];
    fx::decode_q15(v, d[0], d[1]);
    compare(c, d);
#if defined(__AVX2__)
    const fx::F32x8 d8 = fx::decode_q15(v);
    compare(c, &d8);
#endif
  }
  CHECK(bad == 0);
}

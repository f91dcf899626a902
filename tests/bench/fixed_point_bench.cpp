// Costs of the fixed-point operations (docs/fixed_point.md): nanoseconds per
// million operations on L1-resident arrays, median of several runs. Each
// scalar operation is timed twice: one value at a time (vectorisation off
// for that loop) and as GCC compiles a plain loop of it at -O3 (which may
// vectorise it); the explicit vector forms once each.
//   build/tests/bench_fixed_point [runs]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "engine/core/fixed_point.h"
#include "engine/core/fixed_simd.h"
#include "engine/core/hdr16.h"

namespace fx = cr::fx;

namespace {

constexpr int kN = 2048;                    // elements an array: 4 arrays fit in L1
constexpr int kRepeats = (1 << 20) / kN;    // one sample is 2^20 operations

alignas(64) uint16_t ua[kN], ub[kN], uout[kN];
alignas(64) int16_t iw[kN];
alignas(64) uint32_t xa[kN], xout[kN];
alignas(64) float fa[kN], fb[kN], fw[kN], fout[kN];

#define NOVEC __attribute__((noinline, optimize("no-tree-vectorize")))
#define LOOP __attribute__((noinline))

// One pass over the arrays, kN operations.
NOVEC void lerp_scalar() { for (int i = 0; i < kN; ++i) uout[i] = fx::lerp_q15(ua[i], ub[i], iw[i]); }
LOOP void lerp_loop() { for (int i = 0; i < kN; ++i) uout[i] = fx::lerp_q15(ua[i], ub[i], iw[i]); }
LOOP void lerp_x8() {
  for (int i = 0; i < kN; i += 8) {
    fx::U16x8 a, b;
    fx::I16x8 w;
    __builtin_memcpy(&a, &ua[i], 16);
    __builtin_memcpy(&b, &ub[i], 16);
    __builtin_memcpy(&w, &iw[i], 16);
    const fx::U16x8 r = fx::lerp_q15(a, b, w);
    __builtin_memcpy(&uout[i], &r, 16);
  }
}
#if defined(__AVX2__)
LOOP void lerp_x16() {
  for (int i = 0; i < kN; i += 16) {
    fx::U16x16 a, b;
    fx::I16x16 w;
    __builtin_memcpy(&a, &ua[i], 32);
    __builtin_memcpy(&b, &ub[i], 32);
    __builtin_memcpy(&w, &iw[i], 32);
    const fx::U16x16 r = fx::lerp_q15(a, b, w);
    __builtin_memcpy(&uout[i], &r, 32);
  }
}
#endif
// The float lerp the q15 one replaces.
NOVEC void lerp_float_scalar() { for (int i = 0; i < kN; ++i) fout[i] = fa[i] + (fb[i] - fa[i]) * fw[i]; }
LOOP void lerp_float_loop() { for (int i = 0; i < kN; ++i) fout[i] = fa[i] + (fb[i] - fa[i]) * fw[i]; }

NOVEC void encode_scalar() { for (int i = 0; i < kN; ++i) uout[i] = fx::encode_q15(fa[i]); }
LOOP void encode_loop() { for (int i = 0; i < kN; ++i) uout[i] = fx::encode_q15(fa[i]); }
LOOP void encode_x8() {
  for (int i = 0; i < kN; i += 8) {
    fx::F32x4 lo, hi;
    __builtin_memcpy(&lo, &fa[i], 16);
    __builtin_memcpy(&hi, &fa[i + 4], 16);
    const fx::U16x8 r = fx::encode_q15(lo, hi);
    __builtin_memcpy(&uout[i], &r, 16);
  }
}
#if defined(__AVX2__)
LOOP void encode_f32x8() {
  for (int i = 0; i < kN; i += 8) {
    fx::F32x8 x;
    __builtin_memcpy(&x, &fa[i], 32);
    const fx::U16x8 r = fx::encode_q15(x);
    __builtin_memcpy(&uout[i], &r, 16);
  }
}
#endif
NOVEC void decode_scalar() { for (int i = 0; i < kN; ++i) fout[i] = fx::decode_q15(ua[i]); }
LOOP void decode_loop() { for (int i = 0; i < kN; ++i) fout[i] = fx::decode_q15(ua[i]); }
LOOP void decode_x8() {
  for (int i = 0; i < kN; i += 8) {
    fx::U16x8 c;
    __builtin_memcpy(&c, &ua[i], 16);
    fx::F32x4 lo, hi;
    fx::decode_q15(c, lo, hi);
    __builtin_memcpy(&fout[i], &lo, 16);
    __builtin_memcpy(&fout[i + 4], &hi, 16);
  }
}
#if defined(__AVX2__)
LOOP void decode_f32x8() {
  for (int i = 0; i < kN; i += 8) {
    fx::U16x8 c;
    __builtin_memcpy(&c, &ua[i], 16);
    const fx::F32x8 r = fx::decode_q15(c);
    __builtin_memcpy(&fout[i], &r, 32);
  }
}
#endif

NOVEC void mul_unorm16_scalar() { for (int i = 0; i < kN; ++i) uout[i] = fx::mul_unorm16(ua[i], ub[i]); }
LOOP void mul_unorm16_loop() { for (int i = 0; i < kN; ++i) uout[i] = fx::mul_unorm16(ua[i], ub[i]); }
NOVEC void reciprocal_scalar() { for (int i = 0; i < kN; ++i) xout[i] = fx::reciprocal_q16_16(xa[i]); }
NOVEC void exp2_scalar() { for (int i = 0; i < kN; ++i) uout[i] = fx::exp2_neg_q15(xa[i] & 0xFFFFF); }
NOVEC void log2_scalar() { for (int i = 0; i < kN; ++i) xout[i] = uint32_t(fx::log2_q16_16(xa[i])); }
NOVEC void hdr16_encode_scalar() { for (int i = 0; i < kN; ++i) uout[i] = fx::encode_hdr16(fb[i]); }
LOOP void hdr16_encode_loop() { for (int i = 0; i < kN; ++i) uout[i] = fx::encode_hdr16(fb[i]); }
NOVEC void hdr16_decode_scalar() { for (int i = 0; i < kN; ++i) fout[i] = fx::decode_hdr16(ua[i]); }
LOOP void hdr16_decode_loop() { for (int i = 0; i < kN; ++i) fout[i] = fx::decode_hdr16(ua[i]); }

// Median over runs of the nanoseconds for 2^20 operations, scaled to 10^6.
double time_ns_per_million(void (*pass)(), int runs) {
  std::vector<double> ns;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < kRepeats; ++k) {
      pass();
      asm volatile("" ::: "memory");  // each pass really runs
    }
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() * (1e6 / (1 << 20)));
  }
  std::nth_element(ns.begin(), ns.begin() + runs / 2, ns.end());
  return ns[runs / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  std::mt19937 rng(1);
  for (int i = 0; i < kN; ++i) {
    ua[i] = uint16_t(rng() % 32768);
    ub[i] = uint16_t(rng() % 32768);
    iw[i] = int16_t(rng() % 32768);
    xa[i] = std::max<uint32_t>(1, rng());
    fa[i] = float(rng() % 100000) / 90000.0f;  // [0, 1.11]: some saturate
    fb[i] = std::ldexp(float(rng() % 1000 + 1), int(rng() % 60) - 35);
    fw[i] = float(iw[i]) / 32768.0f;
  }
  struct Case {
    const char* name;
    void (*pass)();
  };
  const Case cases[] = {
      {"lerp_q15 scalar", lerp_scalar},
      {"lerp_q15 scalar loop (-O3)", lerp_loop},
      {"lerp_q15 U16x8", lerp_x8},
#if defined(__AVX2__)
      {"lerp_q15 U16x16", lerp_x16},
#endif
      {"float lerp scalar", lerp_float_scalar},
      {"float lerp loop (-O3)", lerp_float_loop},
      {"encode_q15 scalar", encode_scalar},
      {"encode_q15 scalar loop (-O3)", encode_loop},
      {"encode_q15 2 x F32x4", encode_x8},
#if defined(__AVX2__)
      {"encode_q15 F32x8", encode_f32x8},
#endif
      {"decode_q15 scalar", decode_scalar},
      {"decode_q15 scalar loop (-O3)", decode_loop},
      {"decode_q15 U16x8 -> 2 x F32x4", decode_x8},
#if defined(__AVX2__)
      {"decode_q15 U16x8 -> F32x8", decode_f32x8},
#endif
      {"mul_unorm16 scalar", mul_unorm16_scalar},
      {"mul_unorm16 scalar loop (-O3)", mul_unorm16_loop},
      {"reciprocal_q16_16 scalar", reciprocal_scalar},
      {"exp2_neg_q15 scalar", exp2_scalar},
      {"log2_q16_16 scalar", log2_scalar},
      {"encode_hdr16 scalar", hdr16_encode_scalar},
      {"encode_hdr16 scalar loop (-O3)", hdr16_encode_loop},
      {"decode_hdr16 scalar", hdr16_decode_scalar},
      {"decode_hdr16 scalar loop (-O3)", hdr16_decode_loop},
  };
  std::printf("%-34s %14s\n", "operation", "ns per 1M ops");
  for (const Case& c : cases) std::printf("%-34s %14.0f\n", c.name, time_ns_per_million(c.pass, runs));
  uint32_t sum = 0;  // keeps the outputs alive
  for (int i = 0; i < kN; ++i) sum += uout[i] + xout[i] + uint32_t(fout[i]);
  std::printf("(checksum %u)\n", sum);
}

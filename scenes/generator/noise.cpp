#include "scenes/generator/noise.h"

#include <algorithm>
#include <cmath>

namespace cr::gen {

uint32_t hash2(int32_t x, int32_t y, uint32_t seed) {
  // Murmur3-style finaliser over a linear combination of the inputs.
  uint32_t h = seed * 0x9E3779B1u;
  h ^= static_cast<uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<uint32_t>(y) * 0xC2B2AE35u;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

double hash_unit(int32_t x, int32_t y, uint32_t seed) {
  return static_cast<double>(hash2(x, y, seed) >> 8) * (1.0 / 16777216.0);
}

namespace {

double quintic(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

int32_t wrap(int32_t i, int32_t period) {
  if (period <= 0) return i;
  const int32_t m = i % period;
  return m < 0 ? m + period : m;
}

}  // namespace

double value_noise(double x, double y, uint32_t seed, int32_t period) {
  const double fx = std::floor(x);
  const double fy = std::floor(y);
  const auto ix = static_cast<int32_t>(fx);
  const auto iy = static_cast<int32_t>(fy);
  const double tx = quintic(x - fx);
  const double ty = quintic(y - fy);
  const int32_t x0 = wrap(ix, period), x1 = wrap(ix + 1, period);
  const int32_t y0 = wrap(iy, period), y1 = wrap(iy + 1, period);
  const double a = hash_unit(x0, y0, seed), b = hash_unit(x1, y0, seed);
  const double c = hash_unit(x0, y1, seed), d = hash_unit(x1, y1, seed);
  const double top = a + (b - a) * tx;
  const double bottom = c + (d - c) * tx;
  return top + (bottom - top) * ty;
}

double fbm(double x, double y, uint32_t seed, int octaves, double gain, int32_t period) {
  double sum = 0.0, weight = 1.0, total = 0.0, freq = 1.0;
  for (int i = 0; i < octaves; ++i) {
    const int32_t p = period > 0 ? period << i : 0;
    sum += weight * value_noise(x * freq, y * freq, seed + 101u * static_cast<uint32_t>(i), p);
    total += weight;
    weight *= gain;
    freq *= 2.0;
  }
  return sum / total;
}

double ridged_fbm(double x, double y, uint32_t seed, int octaves) {
  double sum = 0.0, weight = 1.0, amplitude = 1.0, total = 0.0, freq = 1.0;
  for (int i = 0; i < octaves; ++i) {
    const double n = value_noise(x * freq, y * freq, seed + 977u * static_cast<uint32_t>(i));
    double ridge = 1.0 - std::abs(2.0 * n - 1.0);
    ridge *= ridge;
    sum += amplitude * ridge * weight;
    total += amplitude;
    weight = std::clamp(ridge * 1.5, 0.0, 1.0);
    amplitude *= 0.5;
    freq *= 2.0;
  }
  return sum / total;
}

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace cr::gen

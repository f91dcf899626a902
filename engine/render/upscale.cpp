#include "engine/render/upscale.h"

#include <algorithm>
#include <cmath>

#include "engine/core/luminance.h"

namespace cr {

namespace {

constexpr size_t kBandRows = 16;  // output rows per job

float luminance(const float* c) { return cr::luminance(glm::vec3(c[0], c[1], c[2])); }

// The inverse's denominator never reaches 0: per-channel clamps may combine
// channels of different pixels into a luminance just above 1.
constexpr float kMinInverse = 1.0f / 65536.0f;

}  // namespace

Upscaler::Upscaler(int source_width, int source_height, int width, int height)
    : source_width_(source_width), width_(width), height_(height),
      columns_(axis_taps(source_width, width)), rows_(axis_taps(source_height, height)) {}

std::vector<Upscaler::Taps> Upscaler::axis_taps(int source, int output) {
  std::vector<Taps> taps(static_cast<size_t>(output));
  const double ratio = double(source) / double(output);
  for (int o = 0; o < output; ++o) {
    // The output pixel's centre in source pixels (whose centres sit at i + 0.5).
    const double centre = (o + 0.5) * ratio;
    const double base = std::floor(centre - 0.5), t = centre - 0.5 - base;
    // Catmull-Rom: the cubic through the four pixels' values with the
    // central differences as slopes at the middle two.
    const double w[4] = {0.5 * (-t * t * t + 2.0 * t * t - t), 0.5 * (3.0 * t * t * t - 5.0 * t * t + 2.0),
                         0.5 * (-3.0 * t * t * t + 4.0 * t * t + t), 0.5 * (t * t * t - t * t)};
    Taps& tap = taps[size_t(o)];
    for (int k = 0; k < 4; ++k) {
      tap.index[k] = std::clamp(int(base) - 1 + k, 0, source - 1);
      tap.weight[k] = float(w[k]);
    }
    tap.nearest = std::min(int(centre), source - 1);
  }
  return taps;
}

void Upscaler::color(const std::vector<glm::vec3>& source, std::vector<glm::vec3>& out, JobSystem& jobs,
                     float exposure) const {
  out.resize(size_t(width_) * size_t(height_));
  const size_t row_floats = 3 * size_t(width_);
  jobs.parallel_for("upscale", size_t(height_), kBandRows, [&](size_t y0, size_t y1) {
    // The band's source rows (non-decreasing in y) are filtered horizontally
    // once, with each output column's min and max of its two bracketing
    // pixels; the vertical filter and the clamp are then float loops over
    // whole rows, which vectorise.
    const int r0 = rows_[y0].index[0], r1 = rows_[y1 - 1].index[3] + 1;
    thread_local std::vector<float> filtered, lo, hi;  // reused: no allocation or page faults per band
    const size_t floats = size_t(r1 - r0) * row_floats;
    if (filtered.size() < floats) {
      filtered.resize(floats);
      lo.resize(floats);
      hi.resize(floats);
    }
    thread_local std::vector<float> compressed;
    if (exposure > 0.0f) compressed.resize(3 * size_t(source_width_));
    for (int r = r0; r < r1; ++r) {
      const float* src = &source[size_t(r) * size_t(source_width_)][0];
      if (exposure > 0.0f) {  // the source row through the reversible tonemap
        for (int x = 0; x < source_width_; ++x) {
          const float* c = src + 3 * x;
          const float s = 1.0f / (1.0f + exposure * luminance(c));
          for (int ch = 0; ch < 3; ++ch) compressed[3 * size_t(x) + size_t(ch)] = c[ch] * s;
        }
        src = compressed.data();
      }
      const size_t row = size_t(r - r0) * row_floats;
      for (int x = 0; x < width_; ++x) {
        const Taps& c = columns_[size_t(x)];
        for (int ch = 0; ch < 3; ++ch) {
          const float a = src[3 * c.index[0] + ch], b = src[3 * c.index[1] + ch], d = src[3 * c.index[2] + ch],
                      e = src[3 * c.index[3] + ch];
          const size_t i = row + 3 * size_t(x) + size_t(ch);
          filtered[i] = a * c.weight[0] + b * c.weight[1] + d * c.weight[2] + e * c.weight[3];
          lo[i] = std::min(b, d);
          hi[i] = std::max(b, d);
        }
      }
    }
    for (size_t y = y0; y < y1; ++y) {
      const Taps& t = rows_[y];
      const auto row = [&](const std::vector<float>& v, int k) { return &v[size_t(t.index[k] - r0) * row_floats]; };
      const float *f0 = row(filtered, 0), *f1 = row(filtered, 1), *f2 = row(filtered, 2), *f3 = row(filtered, 3);
      const float *lo1 = row(lo, 1), *lo2 = row(lo, 2), *hi1 = row(hi, 1), *hi2 = row(hi, 2);
      float* dst = &out[y * size_t(width_)][0];
      for (size_t i = 0; i < row_floats; ++i) {
        const float v = f0[i] * t.weight[0] + f1[i] * t.weight[1] + f2[i] * t.weight[2] + f3[i] * t.weight[3];
        dst[i] = std::min(std::max(v, std::min(lo1[i], lo2[i])), std::max(hi1[i], hi2[i]));
      }
      if (exposure > 0.0f)
        for (int x = 0; x < width_; ++x) {
          float* c = dst + 3 * x;
          const float s = 1.0f / std::max(1.0f - exposure * luminance(c), kMinInverse);
          for (int ch = 0; ch < 3; ++ch) c[ch] *= s;
        }
    }
  });
}

void Upscaler::nearest(const std::vector<float>& source, std::vector<float>& out, JobSystem& jobs) const {
  out.resize(size_t(width_) * size_t(height_));
  jobs.parallel_for("upscale nearest", size_t(height_), kBandRows, [&](size_t y0, size_t y1) {
    for (size_t y = y0; y < y1; ++y) {
      const float* src = &source[size_t(rows_[y].nearest) * size_t(source_width_)];
      float* dst = &out[y * size_t(width_)];
      for (int x = 0; x < width_; ++x) dst[x] = src[columns_[size_t(x)].nearest];
    }
  });
}

}  // namespace cr

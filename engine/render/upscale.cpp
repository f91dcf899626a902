#include "engine/render/upscale.h"

#include <algorithm>
#include <cmath>

namespace cr {

namespace {

constexpr size_t kBandRows = 16;  // output rows per job

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

void Upscaler::color(const std::vector<glm::vec3>& source, std::vector<glm::vec3>& out, JobSystem& jobs) const {
  out.resize(size_t(width_) * size_t(height_));
  jobs.parallel_for("upscale", size_t(height_), kBandRows, [&](size_t y0, size_t y1) {
    // The band's source rows are filtered horizontally once (rows are
    // non-decreasing in y), then combined vertically per output row.
    const int r0 = rows_[y0].index[0], r1 = rows_[y1 - 1].index[3] + 1;
    std::vector<glm::vec3> filtered(size_t(r1 - r0) * size_t(width_));
    for (int r = r0; r < r1; ++r) {
      const glm::vec3* src = &source[size_t(r) * size_t(source_width_)];
      glm::vec3* dst = &filtered[size_t(r - r0) * size_t(width_)];
      for (int x = 0; x < width_; ++x) {
        const Taps& c = columns_[size_t(x)];
        dst[x] = src[c.index[0]] * c.weight[0] + src[c.index[1]] * c.weight[1] + src[c.index[2]] * c.weight[2] +
                 src[c.index[3]] * c.weight[3];
      }
    }
    for (size_t y = y0; y < y1; ++y) {
      const Taps& t = rows_[y];
      const glm::vec3* f[4];
      for (int k = 0; k < 4; ++k) f[k] = &filtered[size_t(t.index[k] - r0) * size_t(width_)];
      const glm::vec3* above = &source[size_t(t.index[1]) * size_t(source_width_)];
      const glm::vec3* below = &source[size_t(t.index[2]) * size_t(source_width_)];
      glm::vec3* dst = &out[y * size_t(width_)];
      for (int x = 0; x < width_; ++x) {
        const glm::vec3 v = f[0][x] * t.weight[0] + f[1][x] * t.weight[1] + f[2][x] * t.weight[2] + f[3][x] * t.weight[3];
        const Taps& c = columns_[size_t(x)];
        const glm::vec3 a = above[c.index[1]], b = above[c.index[2]], d = below[c.index[1]], e = below[c.index[2]];
        dst[x] = glm::clamp(v, glm::min(glm::min(a, b), glm::min(d, e)), glm::max(glm::max(a, b), glm::max(d, e)));
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

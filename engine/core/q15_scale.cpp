#include "engine/core/q15_scale.h"

#include <cmath>

namespace cr {

Q15Scale q15_scale_for(float max_value) {
  Q15Scale s;
  if (!(max_value > 0.0f) || !std::isfinite(max_value)) return s;
  s.scale = max_value * (32768.0f / 32767.0f);
  s.inv_scale = 1.0f / s.scale;
  return s;
}

uint16_t to_q15(float value, const Q15Scale& s) { return fx::encode_q15(value * s.inv_scale); }

float max_value(const float* values, size_t n, size_t stride) {
  float m = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    const float v = values[i * stride];
    if (std::isfinite(v) && v > m) m = v;
  }
  return m;
}

void round_to_q15(float* values, size_t n, size_t stride, const Q15Scale& s) {
  for (size_t i = 0; i < n; ++i) values[i * stride] = from_q15(to_q15(values[i * stride], s), s);
}

}  // namespace cr

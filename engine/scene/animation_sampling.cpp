#include "engine/scene/animation_sampling.h"

#include <algorithm>

namespace cr {

namespace {

// Where a time falls: between keys `key` and `next` at fraction u of the
// interval dt, or on one key (next == key) before the first or after the last.
struct KeySpan {
  size_t key = 0;
  size_t next = 0;
  double u = 0.0;
  double dt = 0.0;
};

KeySpan find_span(const std::vector<float>& times, double time_s) {
  const size_t last = times.size() - 1;
  if (last == 0 || time_s <= times[0]) return {};
  if (time_s >= times[last]) return {last, last};
  // The first key after time_s; time_s is inside (times[0], times[last]).
  const size_t next = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), time_s) - times.begin());
  const size_t key = next - 1;
  const double dt = double(times[next]) - double(times[key]);
  return {key, next, (time_s - double(times[key])) / dt, dt};
}

// CUBICSPLINE stores (in-tangent, value, out-tangent) per key.
enum class KeyPart { InTangent = 0, Value = 1, OutTangent = 2 };

double key_component(const AnimationSampler& s, size_t key, KeyPart part, int c) {
  const size_t element = s.interpolation == Interpolation::CubicSpline ? 3 * key + size_t(part) : key;
  return s.values[element * size_t(s.components) + size_t(c)];
}

double interpolate(const AnimationSampler& s, const KeySpan& span, int c) {
  const double v0 = key_component(s, span.key, KeyPart::Value, c);
  if (span.next == span.key || s.interpolation == Interpolation::Step) return v0;
  const double v1 = key_component(s, span.next, KeyPart::Value, c);
  const double u = span.u;
  if (s.interpolation == Interpolation::Linear) return v0 + (v1 - v0) * u;
  const double u2 = u * u, u3 = u2 * u;
  const double out0 = key_component(s, span.key, KeyPart::OutTangent, c);
  const double in1 = key_component(s, span.next, KeyPart::InTangent, c);
  return (2.0 * u3 - 3.0 * u2 + 1.0) * v0 + span.dt * (u3 - 2.0 * u2 + u) * out0 + (-2.0 * u3 + 3.0 * u2) * v1 +
         span.dt * (u3 - u2) * in1;
}

glm::dquat key_rotation(const AnimationSampler& s, size_t key) {
  auto c = [&](int i) { return key_component(s, key, KeyPart::Value, i); };
  return glm::dquat(c(3), c(0), c(1), c(2));
}

}  // namespace

std::vector<double> sample_values(const AnimationSampler& sampler, double time_s) {
  const KeySpan span = find_span(sampler.times, time_s);
  std::vector<double> out(static_cast<size_t>(sampler.components));
  for (int c = 0; c < sampler.components; ++c) out[size_t(c)] = interpolate(sampler, span, c);
  return out;
}

glm::dquat sample_rotation(const AnimationSampler& sampler, double time_s) {
  const KeySpan span = find_span(sampler.times, time_s);
  if (sampler.interpolation == Interpolation::Linear && span.next != span.key) {
    return glm::normalize(glm::slerp(key_rotation(sampler, span.key), key_rotation(sampler, span.next), span.u));
  }
  // STEP and single keys give a key's (unit) value; the cubic spline of
  // quaternions is taken per component and normalised, as the spec says.
  auto c = [&](int i) { return interpolate(sampler, span, i); };
  return glm::normalize(glm::dquat(c(3), c(0), c(1), c(2)));
}

}  // namespace cr

#pragma once
// Phase functions of participating media: 1/sr, each integrating to 1 over
// the sphere. Every one takes (cos_theta, g): cos_theta the cosine of the
// scattering angle (between the light's travel direction and the scattered
// one, i.e. between the view direction and the direction towards the light),
// g the asymmetry (g > 0 scatters forward, |g| < 1). The templates serve float
// (the renderer) and double (reference renderers).
#include <algorithm>
#include <cmath>
#include <concepts>
#include <type_traits>

#include <glm/gtc/constants.hpp>

#include "engine/core/math_constants.h"

namespace cr {

// 1 / (4 pi): the isotropic phase function.
inline constexpr float kIsotropicPhase = 1.0f / (4.0f * kPi);

template <std::floating_point T>
T rayleigh_phase(T cos_theta) {
  return T(3) / (T(16) * glm::pi<T>()) * (T(1) + cos_theta * cos_theta);
}

// 1 + g^2 - 2 g cos_theta: >= (1 - |g|)^2 > 0 for |g| < 1; the floor (1e-12
// in float, 1e-300 in double) only guards rounding at cos_theta = +-1.
template <std::floating_point T>
T phase_lobe_denominator(T cos_theta, T g) {
  constexpr T floor = std::is_same_v<T, float> ? T(1e-12f) : T(1e-300);
  return std::max(T(1) + g * g - T(2) * g * cos_theta, floor);
}

// Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^(3/2)).
template <std::floating_point T>
T henyey_greenstein(T cos_theta, T g) {
  const T denom = phase_lobe_denominator(cos_theta, g);
  return (T(1) - g * g) / (T(4) * glm::pi<T>() * denom * std::sqrt(denom));
}

// Cornette-Shanks: 3/(8 pi) (1 - g^2)/(2 + g^2) (1 + cos^2)/(1 + g^2 - 2 g cos)^(3/2).
template <std::floating_point T>
T cornette_shanks(T cos_theta, T g) {
  const T g2 = g * g;
  const T denom = phase_lobe_denominator(cos_theta, g);
  return T(3) / (T(8) * glm::pi<T>()) * (T(1) - g2) * (T(1) + cos_theta * cos_theta) /
         ((T(2) + g2) * denom * std::sqrt(denom));
}

// The same two functions with the normalisation (1/(4 pi), 3/(8 pi)) applied
// to the numerator first and (2 + g^2) divided separately: another order of
// the same operations, so another rounding (the last bit differs for about
// half of all arguments). Kept, not merged, because frames and goldens were
// made with each order where it is used (the froxel fog uses these), and a
// merge would change them.
inline float henyey_greenstein_normalized_first(float cos_theta, float g) {
  const float denom = phase_lobe_denominator(cos_theta, g);
  return kIsotropicPhase * (1.0f - g * g) / (denom * std::sqrt(denom));
}
inline float cornette_shanks_normalized_first(float cos_theta, float g) {
  const float denom = phase_lobe_denominator(cos_theta, g);
  return 3.0f / (8.0f * kPi) * (1.0f - g * g) / (2.0f + g * g) * (1.0f + cos_theta * cos_theta) /
         (denom * std::sqrt(denom));
}

}  // namespace cr

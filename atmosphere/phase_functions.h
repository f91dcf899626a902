#pragma once
// Phase functions (1/sr, each integrates to 1 over the sphere) of cos(theta),
// theta the angle between the light's travel direction and the scattered one
// (equivalently, between view-to-sun and view directions).
#include <algorithm>
#include <array>
#include <cmath>

#include "atmosphere/atmosphere_model.h"
#include "engine/core/math_constants.h"

namespace cr {

inline constexpr float kIsotropicPhase = 1.0f / (4.0f * kPi);

inline float rayleigh_phase(float cos_theta) {
  return 3.0f / (16.0f * kPi) * (1.0f + cos_theta * cos_theta);
}

inline float henyey_greenstein_phase(float cos_theta, float g) {
  const float g2 = g * g;
  // >= (1-|g|)^2 > 0 for |g| < 1; the max only guards rounding at cos = +-1.
  const float denom = std::max(1.0f + g2 - 2.0f * g * cos_theta, 1e-12f);
  return (1.0f - g2) / (4.0f * kPi * denom * std::sqrt(denom));
}

inline float cornette_shanks_phase(float cos_theta, float g) {
  const float g2 = g * g;
  const float denom = std::max(1.0f + g2 - 2.0f * g * cos_theta, 1e-12f);
  return 3.0f / (8.0f * kPi) * (1.0f - g2) * (1.0f + cos_theta * cos_theta) /
         ((2.0f + g2) * denom * std::sqrt(denom));
}

inline float mie_phase(const AtmosphereModel& m, float cos_theta) {
  if (m.mie_phase == MiePhaseModel::CornetteShanks) return cornette_shanks_phase(cos_theta, m.mie_g);
  return m.mie_lobe_weight * henyey_greenstein_phase(cos_theta, m.mie_g) +
         (1.0f - m.mie_lobe_weight) * henyey_greenstein_phase(cos_theta, m.mie_g2);
}

// The phase's Legendre coefficients k_l = 2 pi * integral of p(cos) P_l(cos)
// over [-1, 1], for l = 1, 2 (p = sum (2l + 1) / (4 pi) k_l P_l; HG: k_l = g^l).
// Numerical: cos = 1 - 2 s^2 packs the points where forward peaks are.
inline std::array<double, 2> mie_legendre_coefficients(const AtmosphereModel& m) {
  constexpr int n = 4096;
  double k1 = 0.0, k2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double s = (double(i) + 0.5) / n;
    const double c = 1.0 - 2.0 * s * s;
    const double p = double(mie_phase(m, float(c))) * 4.0 * s / n;  // dcos = 4 s ds
    k1 += p * c;
    k2 += p * 0.5 * (3.0 * c * c - 1.0);
  }
  return {2.0 * kPiD * k1, 2.0 * kPiD * k2};
}

}  // namespace cr

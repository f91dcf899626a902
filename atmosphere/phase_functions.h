#pragma once
// The atmosphere's Mie phase function (the model's Cornette-Shanks or double
// Henyey-Greenstein lobes) and its Legendre coefficients; the phase functions
// themselves, and their argument order (cos_theta, g), are
// engine/shading/phase_functions.h's.
#include <array>

#include "atmosphere/atmosphere_model.h"
#include "engine/core/math_constants.h"
#include "engine/shading/phase_functions.h"

namespace cr {

inline float mie_phase(const AtmosphereModel& m, float cos_theta) {
  if (m.mie_phase == MiePhaseModel::CornetteShanks) return cornette_shanks(cos_theta, m.mie_g);
  return m.mie_lobe_weight * henyey_greenstein(cos_theta, m.mie_g) +
         (1.0f - m.mie_lobe_weight) * henyey_greenstein(cos_theta, m.mie_g2);
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

#pragma once
// Inline density evaluation for the ray-march inner loops.
#include <algorithm>
#include <cmath>

#include "atmosphere/atmosphere_model.h"
#include "engine/core/fast_math.h"

namespace cr {

inline Densities DensityProfile::at(float altitude) const {
  // Below the ground (camera under terrain, pushed froxels) the ground density holds.
  const float h = altitude > 0.0f ? altitude : 0.0f;
  const float ozone = 1.0f - std::fabs(h - ozone_center) * inv_ozone_half_width;
  return {fast_exp_neg(-h * inv_rayleigh_height), fast_exp_neg(-h * inv_mie_height), ozone > 0.0f ? ozone : 0.0f};
}

// Scattering and extinction from densities (coefficients of the model).
inline MediumSample medium_from(const AtmosphereModel& m, const Densities& d) {
  MediumSample s;
  s.rayleigh_scattering = m.rayleigh_scattering * d.rayleigh;
  s.mie_scattering = m.mie_scattering * d.mie;
  s.scattering = s.rayleigh_scattering + s.mie_scattering;
  s.extinction = s.scattering + m.mie_absorption * d.mie + m.ozone_absorption * d.ozone;
  return s;
}

}  // namespace cr

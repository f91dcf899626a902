#pragma once
// The fog medium's phase function (normalised over the sphere, 1/sr) and its
// convolution with SH L2 ambient light.
// cos_theta is the cosine between the direction the camera looks along and
// the direction towards the light: forward scattering (g > 0) brightens the
// fog when looking towards the sun. Arguments in the order of
// engine/shading/phase_functions.h: (cos_theta, g).
#include <array>

#include <glm/glm.hpp>

#include "fog/fog_settings.h"

namespace cr {

// The scene's phase function (Henyey-Greenstein or Cornette-Shanks, in
// engine/shading/phase_functions.h) with asymmetry g.
float evaluate_phase(FogPhase phase, float cos_theta, float g);

// Zonal (Legendre) coefficients lambda_l, l = 0..2, of a phase function:
// convolving SH band l with the phase scales it by lambda_l (Funk-Hecke).
// HG: g^l. CS: closed form from the HG moments E[P_l] = g^l.
std::array<float, 3> phase_zonal_coefficients(FogPhase phase, float g);

// In-scattered ambient radiance fraction for a view direction: the integral of
// phase(view, w) * L(w) over the sphere, L given by real SH L2 coefficients
// (LightEnvironment::ambient_sh order).
glm::vec3 phase_convolved_ambient(const std::array<glm::vec3, 9>& sh, const std::array<float, 3>& zonal,
                                  const glm::vec3& view_dir);

}  // namespace cr

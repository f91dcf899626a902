#pragma once
// Phase functions of the fog medium (normalised over the sphere, 1/sr) and
// their convolution with SH L2 ambient light.
// cos_theta is the cosine between the direction the camera looks along and
// the direction towards the light: forward scattering (g > 0) brightens the
// fog when looking towards the sun.
#include <array>

#include <glm/glm.hpp>

#include "fog/fog_settings.h"

namespace cr {

float henyey_greenstein(float g, float cos_theta);
// Cornette-Shanks: 3/(8 pi) (1 - g^2)/(2 + g^2) (1 + mu^2)/(1 + g^2 - 2 g mu)^(3/2).
float cornette_shanks(float g, float cos_theta);
float evaluate_phase(FogPhase phase, float g, float cos_theta);

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

#include "fog/phase_function.h"

#include "engine/shading/phase_functions.h"
#include "engine/shading/sh_lighting.h"

namespace cr {

float evaluate_phase(FogPhase phase, float cos_theta, float g) {
  return phase == FogPhase::CornetteShanks ? cornette_shanks_normalized_first(cos_theta, g)
                                           : henyey_greenstein_normalized_first(cos_theta, g);
}

std::array<float, 3> phase_zonal_coefficients(FogPhase phase, float g) {
  if (phase == FogPhase::HenyeyGreenstein) return {1.0f, g, g * g};
  // CS = HG * (3/2)(1 + mu^2)/(2 + g^2); with (1 + mu^2) P_l written in
  // Legendre polynomials, each term's HG expectation is g^l.
  const double gd = g, g2 = gd * gd, g4 = g2 * g2;
  const double l1 = 3.0 * gd * (4.0 + g2) / (5.0 * (2.0 + g2));
  const double l2 = (4.0 * g2 + 36.0 * g4 / 35.0 + 4.0 * g2 / 7.0 + 2.0 / 5.0) / (2.0 * (2.0 + g2));
  return {1.0f, float(l1), float(l2)};
}

glm::vec3 phase_convolved_ambient(const std::array<glm::vec3, 9>& sh, const std::array<float, 3>& zonal,
                                  const glm::vec3& view_dir) {
  const std::array<float, 9> y = sh_basis(view_dir);
  glm::vec3 sum(0.0f);
  // Coefficient i is in band 0, 1 (i = 1..3) or 2 (i = 4..8). Indexing
  // zonal directly, not through a per-call table of 9 band factors: GCC packs
  // such a table with scalar stores and reloads it as one vector, a
  // store-forwarding stall that cost more than the sum itself.
  for (size_t i = 0; i < 9; ++i) sum += sh[i] * (zonal[i == 0 ? 0 : i < 4 ? 1 : 2] * y[i]);
  // Band-limited light may ring below zero; radiance cannot.
  return glm::max(sum, glm::vec3(0.0f));
}

}  // namespace cr

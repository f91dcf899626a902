#include "fog/phase_function.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/sh_lighting.h"

namespace cr {

namespace {
constexpr float kInvFourPi = 0.07957747154594767f;
constexpr float kThreeOverEightPi = 0.11936620731892151f;
}  // namespace

float henyey_greenstein(float g, float cos_theta) {
  const float denom = std::max(1.0f + g * g - 2.0f * g * cos_theta, 1e-12f);
  return kInvFourPi * (1.0f - g * g) / (denom * std::sqrt(denom));
}

float cornette_shanks(float g, float cos_theta) {
  const float denom = std::max(1.0f + g * g - 2.0f * g * cos_theta, 1e-12f);
  return kThreeOverEightPi * (1.0f - g * g) / (2.0f + g * g) * (1.0f + cos_theta * cos_theta) /
         (denom * std::sqrt(denom));
}

float evaluate_phase(FogPhase phase, float g, float cos_theta) {
  return phase == FogPhase::CornetteShanks ? cornette_shanks(g, cos_theta) : henyey_greenstein(g, cos_theta);
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

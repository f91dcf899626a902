#include "engine/shading/sh_lighting.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/math_constants.h"

namespace cr {
namespace {

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n, as in
// Numerical Recipes' gauleg); fixed iteration, so the nodes are reproducible.
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(size_t(n), 0.0);
  w.assign(size_t(n), 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPiD * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1.0, p1 = 0.0;
      for (int j = 1; j <= n; ++j) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p2) / j;
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      const double dz = p0 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[size_t(i)] = -z;
    x[size_t(n - 1 - i)] = z;
    w[size_t(i)] = w[size_t(n - 1 - i)] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

}  // namespace

glm::vec3 sh_radiance(const ShCoefficients& c, const glm::vec3& d) {
  const std::array<float, 9> y = sh_basis(d);
  glm::vec3 sum(0.0f);
  for (size_t i = 0; i < 9; ++i) sum += c[i] * y[i];
  return sum;
}

glm::vec3 sh_irradiance(const ShCoefficients& c, const glm::vec3& n) {
  constexpr float kBand[3] = {float(kPiD), float(2.0 * kPiD / 3.0), float(kPiD / 4.0)};
  const std::array<float, 9> y = sh_basis(n);
  glm::vec3 sum = kBand[0] * c[0] * y[0];
  for (size_t i = 1; i < 4; ++i) sum += kBand[1] * c[i] * y[i];
  for (size_t i = 4; i < 9; ++i) sum += kBand[2] * c[i] * y[i];
  return sum;
}

ShLighting::ShLighting(const ShCoefficients& c) : radiance_(c), irradiance_{}, constant_(true) {
  constexpr float kBand[3] = {float(kPiD), float(2.0 * kPiD / 3.0), float(kPiD / 4.0)};
  // The same products as sh_irradiance's kBand[l] * c[i], so the sums match.
  for (size_t i = 0; i < 9; ++i) irradiance_[i] = kBand[i == 0 ? 0 : (i < 4 ? 1 : 2)] * c[i];
  for (size_t i = 1; i < 9; ++i) constant_ = constant_ && c[i] == glm::vec3(0.0f);
}

// Both sums of sh_radiance and sh_irradiance in their order: c_0 Y_0 first,
// then the others (sh_radiance's leading 0 + x is x).
glm::vec3 ShLighting::evaluate(const ShCoefficients& c, const glm::vec3& d) {
  const std::array<float, 9> y = sh_basis(d);
  glm::vec3 sum = c[0] * y[0];
  for (size_t i = 1; i < 9; ++i) sum += c[i] * y[i];
  return sum;
}

ShCoefficients sh_constant_radiance(const glm::vec3& radiance) {
  ShCoefficients c{};
  // L = c0 * Y00 with Y00 = 1 / (2 sqrt(pi)).
  c[0] = radiance * float(2.0 * std::sqrt(kPiD));
  return c;
}

ShCoefficients sh_project(const std::function<glm::vec3(const glm::vec3&)>& radiance, int cos_nodes,
                          int azimuth_nodes) {
  cos_nodes = std::max(cos_nodes, 2);
  azimuth_nodes = std::max(azimuth_nodes, 3);
  std::vector<double> nodes, weights;
  gauss_legendre(cos_nodes, nodes, weights);
  std::array<glm::dvec3, 9> sum{};
  const double azimuth_weight = 2.0 * kPiD / azimuth_nodes;
  for (int i = 0; i < cos_nodes; ++i) {
    const double cos_theta = nodes[size_t(i)];
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    for (int j = 0; j < azimuth_nodes; ++j) {
      const double phi = (j + 0.5) * azimuth_weight;
      // Polar axis +Y (up), azimuth in the XZ plane.
      const glm::vec3 d(float(sin_theta * std::cos(phi)), float(cos_theta), float(sin_theta * std::sin(phi)));
      const glm::dvec3 value(radiance(d));
      const std::array<float, 9> y = sh_basis(d);
      const double w = weights[size_t(i)] * azimuth_weight;
      for (size_t k = 0; k < 9; ++k) sum[k] += value * (w * double(y[k]));
    }
  }
  ShCoefficients c{};
  for (size_t k = 0; k < 9; ++k) c[k] = glm::vec3(sum[k]);
  return c;
}

}  // namespace cr

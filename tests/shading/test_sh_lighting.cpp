#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/shading/sh_lighting.h"

using namespace cr;

namespace {

// Directions spread over the whole sphere (including the poles and axes).
std::vector<glm::vec3> test_directions() {
  std::vector<glm::vec3> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int i = 0; i < 40; ++i) {
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / 40.0f;
    const float phi = 2.39996323f * float(i);  // golden angle spiral
    const float r = std::sqrt(1.0f - z * z);
    dirs.push_back({r * std::cos(phi), z, r * std::sin(phi)});
  }
  return dirs;
}

}  // namespace

TEST_CASE("SH: constant radiance L gives irradiance pi L for any normal") {
  const glm::vec3 L(0.5f, 1.0f, 2.0f);
  const ShCoefficients c = sh_constant_radiance(L);
  const ShCoefficients projected = sh_project([&](const glm::vec3&) { return L; });
  for (const glm::vec3& n : test_directions()) {
    const glm::vec3 e = sh_irradiance(c, n);
    const glm::vec3 r = sh_radiance(c, n);
    for (int k = 0; k < 3; ++k) {
      CHECK(e[k] == doctest::Approx(kPi * L[k]).epsilon(1e-5));
      CHECK(r[k] == doctest::Approx(L[k]).epsilon(1e-5));
    }
  }
  for (size_t i = 0; i < 9; ++i) {
    for (int k = 0; k < 3; ++k) CHECK(projected[i][k] == doctest::Approx(c[i][k]).epsilon(1e-5).scale(1.0));
  }
}

TEST_CASE("SH: basis is orthonormal under the projection quadrature") {
  for (size_t i = 0; i < 9; ++i) {
    // Project Y_i itself: the coefficients must be the unit vector e_i.
    const ShCoefficients c = sh_project([&](const glm::vec3& d) { return glm::vec3(sh_basis(d)[i]); });
    for (size_t j = 0; j < 9; ++j) CHECK(c[j].x == doctest::Approx(i == j ? 1.0f : 0.0f).scale(1.0).epsilon(1e-5));
  }
}

TEST_CASE("SH: clamped cosine lobe projects to A_l Y_lm and reconstructs within the L2 error") {
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, 0.8f, -0.5f));
  const ShCoefficients c =
      sh_project([&](const glm::vec3& d) { return glm::vec3(std::max(0.0f, glm::dot(d, axis))); }, 64, 128);
  // Funk-Hecke: the lobe's coefficients are the convolution constants A_l.
  const std::array<float, 9> y = sh_basis(axis);
  const float band[9] = {kPi, 2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4, kPi / 4, kPi / 4, kPi / 4, kPi / 4};
  for (size_t i = 0; i < 9; ++i) CHECK(c[i].x == doctest::Approx(band[i] * y[i]).scale(1.0).epsilon(2e-3));
  // Reconstruction: band-2 truncation of max(0, cos) is off by at most ~0.1
  // (1.0625 at the axis, 0.094 at the horizon, 0.0625 opposite).
  for (const glm::vec3& d : test_directions()) {
    const float exact = std::max(0.0f, glm::dot(d, axis));
    CHECK(std::abs(sh_radiance(c, d).x - exact) < 0.1f);
  }
  CHECK(sh_radiance(c, axis).x == doctest::Approx(1.0625f).epsilon(3e-3));
}

TEST_CASE("SH: irradiance of a linear radiance gradient is exact") {
  // L(w) = 1 + w.e  ->  E(n) = pi + (2 pi / 3) n.e (bands 0 and 1 only).
  const glm::vec3 e = glm::normalize(glm::vec3(-0.2f, 1.0f, 0.4f)) * 0.8f;
  const ShCoefficients c = sh_project([&](const glm::vec3& d) { return glm::vec3(1.0f + glm::dot(d, e)); }, 4, 6);
  for (const glm::vec3& n : test_directions()) {
    CHECK(sh_irradiance(c, n).x == doctest::Approx(kPi + 2.0f * kPi / 3.0f * glm::dot(n, e)).epsilon(1e-5));
  }
}

TEST_CASE("SH: projection is deterministic") {
  auto sky = [](const glm::vec3& d) { return glm::vec3(1.0f + std::exp(-8.0f * std::abs(d.y)), 2.0f, d.x * d.x); };
  const ShCoefficients a = sh_project(sky), b = sh_project(sky);
  for (size_t i = 0; i < 9; ++i) CHECK(a[i] == b[i]);
}

TEST_CASE("SH: ShLighting gives sh_radiance and sh_irradiance bit for bit") {
  ShCoefficients ringing = sh_constant_radiance(glm::vec3(3.0f, 2.0f, 1.0f));
  for (size_t i = 1; i < 9; ++i) ringing[i] = glm::vec3(0.3f * float(i), -0.2f * float(i), 0.1f);
  // The second set takes ShLighting's constant-radiance path.
  for (const ShCoefficients& c : {ringing, sh_constant_radiance(glm::vec3(1000.0f, 20.0f, 0.5f))}) {
    const ShLighting lighting(c);
    for (const glm::vec3& d : test_directions()) {
      const glm::vec3 r = lighting.radiance(d), e = lighting.irradiance(d);
      const glm::vec3 r_ref = sh_radiance(c, d), e_ref = sh_irradiance(c, d);
      for (int k = 0; k < 3; ++k) {
        CHECK(r[k] == r_ref[k]);
        CHECK(e[k] == e_ref[k]);
      }
    }
  }
}

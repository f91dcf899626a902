#pragma once
// Real spherical harmonics up to band 2 (9 coefficients) for ambient light:
// basis evaluation, irradiance by the Ramamoorthi-Hanrahan convolution
// (A0 = pi, A1 = 2pi/3, A2 = pi/4), projection of a radiance function by a
// fixed quadrature, and constant radiance.
//
// Basis order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22 with the usual
// Cartesian forms (Y1-1 ~ y, Y10 ~ z, Y11 ~ x, ...) in world coordinates: the
// formulas' z is world z, not up. Any fixed choice spans the same space, and
// every producer and consumer of LightEnvironment::ambient_sh uses these.
#include <array>
#include <functional>

#include <glm/glm.hpp>

namespace cr {

using ShCoefficients = std::array<glm::vec3, 9>;

// The nine basis functions at unit direction d (inline: batched shading
// loops evaluate it per lane).
inline std::array<float, 9> sh_basis(const glm::vec3& d) {
  const float x = d.x, y = d.y, z = d.z;
  return {0.282094792f,
          0.488602512f * y,
          0.488602512f * z,
          0.488602512f * x,
          1.092548431f * x * y,
          1.092548431f * y * z,
          0.315391565f * (3.0f * z * z - 1.0f),
          1.092548431f * x * z,
          0.546274215f * (x * x - y * y)};
}
// Radiance reconstructed in direction d: sum_i c_i Y_i(d) (may ring below 0).
glm::vec3 sh_radiance(const ShCoefficients& c, const glm::vec3& d);
// Irradiance on a surface with unit normal n: sum_l A_l sum_m c_lm Y_lm(n).
glm::vec3 sh_irradiance(const ShCoefficients& c, const glm::vec3& n);
// sh_radiance and sh_irradiance of one set of coefficients at many points,
// with the same results: the band factors A_l are folded into a second
// coefficient set once, and radiance constant over the sphere (all but c_0
// zero, e.g. a flat ambient) evaluates to a constant without the basis.
class ShLighting {
 public:
  explicit ShLighting(const ShCoefficients& c);
  glm::vec3 radiance(const glm::vec3& d) const { return constant_ ? radiance_[0] * kY00 : evaluate(radiance_, d); }
  glm::vec3 irradiance(const glm::vec3& n) const {
    return constant_ ? irradiance_[0] * kY00 : evaluate(irradiance_, n);
  }
  // The coefficients radiance() and irradiance() sum (c_0 Y_0 first, then
  // the others in order), for batched evaluation.
  const ShCoefficients& radiance_coefficients() const { return radiance_; }
  const ShCoefficients& irradiance_coefficients() const { return irradiance_; }

 private:
  static constexpr float kY00 = 0.282094792f;
  static glm::vec3 evaluate(const ShCoefficients& c, const glm::vec3& d);
  ShCoefficients radiance_;
  ShCoefficients irradiance_;  // A_l c_lm
  bool constant_;
};

// Coefficients of radiance constant over the sphere (irradiance pi * L).
ShCoefficients sh_constant_radiance(const glm::vec3& radiance);

// Projects radiance(direction) onto the basis with a product quadrature:
// Gauss-Legendre in the cosine of the angle from world +Y (so the horizon,
// where sky radiance changes fastest, gets its nodes) times uniform steps in
// azimuth. Deterministic: the same nodes and summation order every call.
// Radiance of band <= 2 projects exactly from 3 x 5 nodes up; the defaults
// (16 x 32) resolve a clear sky to well within the basis' own error.
ShCoefficients sh_project(const std::function<glm::vec3(const glm::vec3&)>& radiance, int cos_nodes = 16,
                          int azimuth_nodes = 32);

}  // namespace cr

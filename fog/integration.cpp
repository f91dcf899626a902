// fog.integrate: front-to-back integration along each column. Inside a froxel
// the medium is homogeneous (extinction sigma, scattering sigma_s) and the
// source J = sigma_s (phase * sun + ambient) is constant, so one slice of
// length dt adds T * J (1 - exp(-sigma dt)) / sigma and multiplies T by
// exp(-sigma dt) (exact, no step-size error). The phase function and the
// phase-convolved SH ambient use the column's centre direction.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/phase_function.h"

namespace cr {

void integrate_columns(const FroxelView& view, const std::vector<FogDensity>& density,
                       const std::vector<glm::vec3>& sun_light, const MediumLighting& lighting, JobSystem& jobs,
                       std::vector<IntegratedFroxel>& volume) {
  const FroxelGrid& g = view.grid;
  volume.resize(g.count());
  const int nx = g.nx(), nz = g.nz();
  std::vector<float> dt(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) dt[size_t(k)] = g.thickness(k);
  const std::array<float, 3> zonal = phase_zonal_coefficients(lighting.phase, lighting.anisotropy);
  jobs.parallel_for("fog.integrate", size_t(g.ny()), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        const glm::vec3 dir = view.directions[size_t(y) * nx + x];
        const float phase =
            evaluate_phase(lighting.phase, lighting.anisotropy, glm::dot(dir, lighting.sun_direction));
        const glm::vec3 ambient = phase_convolved_ambient(lighting.ambient_sh, zonal, dir);
        const size_t base = g.index(x, y, 0);
        glm::vec3 in_scatter(0.0f);
        float transmittance = 1.0f;
        for (int k = 0; k < nz; ++k) {
          const FogDensity& d = density[base + k];
          const float sigma = d.extinction;
          const float optical = sigma * dt[size_t(k)];
          // (1 - exp(-x)) / sigma with its limit dt for x -> 0.
          const float opacity = opacity_of(optical);
          const float weight = optical > 1e-6f ? opacity / sigma : dt[size_t(k)];
          const glm::vec3 source = d.scattering * (sun_light[base + k] * phase + ambient);
          in_scatter += source * (transmittance * weight);
          transmittance *= 1.0f - opacity;
          volume[base + k] = IntegratedFroxel{in_scatter, transmittance, sigma};
        }
      }
  });
}

}  // namespace cr

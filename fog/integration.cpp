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
    std::vector<float> opacity(static_cast<size_t>(nz)), weight(static_cast<size_t>(nz));
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        const size_t c = size_t(y) * nx + x;
        const int n = view.active_slices[c];
        if (n == 0) continue;
        const glm::vec3 dir = view.directions[c];
        const float phase =
            evaluate_phase(lighting.phase, lighting.anisotropy, glm::dot(dir, lighting.sun_direction));
        const glm::vec3 ambient = phase_convolved_ambient(lighting.ambient_sh, zonal, dir);
        const size_t base = g.index(x, y, 0);
        const FogDensity* d = density.data() + base;
        // Per slice, independent of the others (vectorised): opacity and the
        // slice's weight (1 - exp(-x)) / sigma, with its limit dt for x -> 0.
        for (int k = 0; k < n; ++k) {
          const float sigma = d[k].extinction;
          const float optical = sigma * dt[size_t(k)];
          const float o = opacity_of(optical);
          opacity[size_t(k)] = o;
          weight[size_t(k)] = optical > 1e-6f ? o / sigma : dt[size_t(k)];
        }
        // The front-to-back recurrence.
        const glm::vec3* sun = sun_light.data() + base;
        IntegratedFroxel* out = volume.data() + base;
        glm::vec3 in_scatter(0.0f);
        float transmittance = 1.0f;
        for (int k = 0; k < n; ++k) {
          const glm::vec3 source = d[k].scattering * (sun[k] * phase + ambient);
          in_scatter += source * (transmittance * weight[size_t(k)]);
          transmittance *= 1.0f - opacity[size_t(k)];
          out[k] = IntegratedFroxel{in_scatter, transmittance, d[k].extinction};
        }
      }
  });
}

}  // namespace cr

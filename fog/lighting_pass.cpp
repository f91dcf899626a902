// fog.lighting: sun light per froxel, sampled at one point of the froxel per
// frame. The point is importance sampled along the (jittered) ray inside the
// slice proportionally to the transmittance of the homogeneous froxel
// (seed 002, "closed-form tracking"): with u uniform in [0,1),
//   offset = -log(1 - u (1 - exp(-sigma dt))) / sigma,
// whose weight (1 - exp(-sigma dt)) / sigma is applied at integration, so the
// stored value is the transmittance-weighted mean of E_sun * visibility over
// the slice. u comes from the 7-frame sequence plus a per-column hash.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"
#include "fog/homogeneous_medium.h"
#include "fog/jitter_sequence.h"

namespace cr {

void light_froxels(const FroxelView& view, const std::vector<FogDensity>& density, const SunLightingInputs& sun,
                   const VolumeShadow& shadow, const JitterInputs& jitter, JobSystem& jobs,
                   std::vector<glm::vec3>& sun_light) {
  const FroxelGrid& g = view.grid;
  const Camera& cam = view.camera;
  sun_light.resize(g.count());
  const int nx = g.nx(), nz = g.nz();
  const int samples = std::max(jitter.samples, 1);
  std::vector<float> t0(static_cast<size_t>(nz)), dt(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) {
    t0[size_t(k)] = g.boundary(k);
    dt[size_t(k)] = g.thickness(k);
  }
  const float t_first = g.center(0), t_last = g.center(nz - 1);
  const float s = float(g.froxel_size());
  jobs.parallel_for("fog.lighting", size_t(g.ny()), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < nx; ++x) {
        glm::vec3* out = sun_light.data() + g.index(x, y, 0);
        const FogDensity* column = density.data() + g.index(x, y, 0);
        const int n = view.lit_slices[size_t(y) * nx + x];
        for (int k = 0; k < n; ++k) out[k] = glm::vec3(0.0f);
        if (n == 0) continue;
        const glm::vec2 center_px = g.column_center_px(x, y);
        const float hash = column_hash(x, y);
        for (int i = 0; i < samples; ++i) {
          FroxelJitter j;
          if (jitter.enabled) j = froxel_jitter(jitter.frame + i);
          else if (samples > 1) j.depth = (float(i) + 0.5f) / float(samples);
          const float u = std::fmod(hash + j.depth, 1.0f);
          const glm::vec3 dir =
              cam.ray_direction(center_px.x + j.lateral.x * s, center_px.y + j.lateral.y * s, g.width(), g.height());
          const VolumeShadow::Ray ray = shadow.ray(glm::vec3(0.0f), dir);
          // The sun's illuminance varies slowly (atmospheric transmittance
          // with altitude): evaluate it at the column's ends, lerp in t.
          glm::vec3 e0 = sun.illuminance, e1 = sun.illuminance;
          if (sun.light && sun.light->sun_at) {
            const glm::vec3 ends[2] = {glm::vec3(sun.camera_position + glm::dvec3(dir * t_first)),
                                       glm::vec3(sun.camera_position + glm::dvec3(dir * t_last))};
            glm::vec3 e[2];
            sun.light->sun_at(ends, e, 2);
            e0 = e[0];
            e1 = e[1];
          }
          const glm::vec3 de = nz > 1 ? (e1 - e0) / (t_last - t_first) : glm::vec3(0.0f);
          for (int k = 0; k < n; ++k) {
            if (column[k].scattering == glm::vec3(0.0f)) continue;  // clear air: the light is never used
            const float sigma = std::max(column[k].extinction, 1e-12f);
            const float t = t0[size_t(k)] + importance_sample_offset(u, sigma, dt[size_t(k)]);
            const glm::vec3 e = e0 + de * (t - t_first);
            out[k] += glm::max(e, glm::vec3(0.0f)) * shadow.visibility(ray, t);
          }
        }
        if (samples > 1)
          for (int k = 0; k < n; ++k) out[k] /= float(samples);
      }
  });
}

}  // namespace cr

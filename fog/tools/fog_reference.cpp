#include "fog/tools/fog_reference.h"

#include <algorithm>
#include <cmath>

#include "fog/fog_medium.h"
#include "fog/homogeneous_medium.h"
#include "fog/phase_function.h"

namespace cr {

FogReferenceImage render_fog_reference(const FogSceneSettings& scene, float fog_distance, const Camera& camera,
                                       int width, int height, const LightEnvironment& light,
                                       const ShadowMap& shadow, const std::vector<float>& distance, int samples,
                                       JobSystem& jobs) {
  FogReferenceImage img;
  img.width = width;
  img.height = height;
  img.in_scatter.assign(size_t(width) * height, glm::vec3(0.0f));
  img.transmittance.assign(size_t(width) * height, 1.0f);
  FogMedium medium(scene);
  medium.set_camera(camera.position);
  const std::array<float, 3> zonal = phase_zonal_coefficients(scene.phase, scene.anisotropy);
  const float near = camera.znear, far = camera.znear + fog_distance;
  const int n = std::max(samples, 1);
  jobs.parallel_for("fog.reference", size_t(height), 1, [&](size_t begin, size_t end) {
    for (int y = int(begin); y < int(end); ++y)
      for (int x = 0; x < width; ++x) {
        const size_t i = size_t(y) * width + x;
        const float d = distance[i];
        if (!(d > near)) continue;
        const float length = std::min(d, far) - near;
        const glm::vec3 dir = camera.ray_direction(float(x) + 0.5f, float(y) + 0.5f, width, height);
        const float phase = evaluate_phase(scene.phase, glm::dot(dir, light.sun_direction), scene.anisotropy);
        const glm::vec3 ambient = phase_convolved_ambient(light.ambient_sh, zonal, dir);
        const float step = length / float(n);
        glm::vec3 in_scatter(0.0f);
        float transmittance = 1.0f;
        for (int s = 0; s < n; ++s) {
          const float t = near + (float(s) + 0.5f) * step;
          const glm::vec3 rel = dir * t;
          const FogDensity m = medium.sample(rel);
          if (m.extinction <= 0.0f) continue;
          const glm::vec3 world(camera.position + glm::dvec3(rel));
          glm::vec3 sun(0.0f);
          if (glm::any(glm::greaterThan(m.scattering, glm::vec3(0.0f)))) {
            const glm::vec3 e = sun_illuminance_at(light, world);
            sun = glm::max(e, glm::vec3(0.0f)) * shadow.visibility(world, glm::vec3(0.0f));
          }
          const float opacity = opacity_of(m.extinction * step);
          in_scatter += m.scattering * (sun * phase + ambient) * (transmittance * opacity / m.extinction);
          transmittance *= 1.0f - opacity;
        }
        img.in_scatter[i] = in_scatter;
        img.transmittance[i] = transmittance;
      }
  });
  return img;
}

}  // namespace cr

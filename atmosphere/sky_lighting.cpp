#include "atmosphere/sky_lighting.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/phase_functions.h"
#include "atmosphere/sky_composite.h"
#include "engine/shading/sh_lighting.h"

namespace cr {

std::array<glm::vec3, 9> sky_ambient_sh(const SkyFrame& f) {
  if (!f.valid) return {};
  return sh_project([&f](const glm::vec3& d) { return sky_radiance(f, d, false); });
}

void fill_light_environment(const SkyFrame& f, LightEnvironment& light,
                            std::shared_ptr<const SpecularEnvironment> specular) {
  light.sun_direction = f.sun;
  if (!f.valid) return;
  light.sun_illuminance = f.sun_illuminance * f.transmittance->sun(f.camera_row, f.mu_s);
  light.ambient_sh = sky_ambient_sh(f);
  light.specular = std::move(specular);
  // The lambda owns its LUT snapshot: shading may run while the next frame republishes.
  std::shared_ptr<const TransmittanceLut> lut = f.transmittance;
  const glm::dvec3 offset = f.planet_offset;
  const glm::vec3 sun = f.sun;
  const glm::vec3 e = f.sun_illuminance;
  const double ground = f.model.bottom_radius;
  light.sun_at = [lut, offset, sun, e, ground](const glm::vec3* world_pos, glm::vec3* out, size_t n) {
    // Altitude and sun cosine of a chunk of points first, in a loop the
    // compiler vectorises, then the batched LUT lookups.
    constexpr size_t kChunk = 64;
    float altitude[kChunk], mu_s[kChunk];
    const glm::dvec3 s(sun);
    for (size_t begin = 0; begin < n; begin += kChunk) {
      const size_t count = std::min(kChunk, n - begin);
      for (size_t i = 0; i < count; ++i) {
        const glm::dvec3 p = glm::dvec3(world_pos[begin + i]) + offset;
        const double r = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        altitude[i] = float(r - ground);
        mu_s[i] = float((p.x * s.x + p.y * s.y + p.z * s.z) / r);
      }
      lut->sun_batch(altitude, mu_s, count, out + begin);
      for (size_t i = 0; i < count; ++i) out[begin + i] = e * out[begin + i];
    }
  };
}

}  // namespace cr

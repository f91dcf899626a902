#include "fog/tools/synthetic_fog_view.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "engine/shading/sh_lighting.h"

namespace cr {

LightEnvironment synthetic_light(const glm::vec3& sun_dir, float sun_lux, float ambient) {
  LightEnvironment l;
  l.sun_direction = glm::normalize(sun_dir);
  l.sun_illuminance = glm::vec3(sun_lux);
  l.ambient_sh = sh_constant_radiance(glm::vec3(ambient));
  return l;
}

ShadowMap wall_shadow_map(const Camera& cam, const glm::vec3& sun_dir, float wall_height) {
  ShadowMap m = fit_shadow_map(cam, glm::normalize(sun_dir), 120.0f, 512, 1, glm::vec3(-200, 0, -200),
                               glm::vec3(200, 60, 200));
  // Each texel's sun ray is linear in NDC z: intersect it with the wall box
  // (slabs in x and y) and record the sunward end of the overlap.
  const glm::mat4 inv = glm::inverse(m.light_view_proj);
  for (int row = 0; row < m.size; ++row)
    for (int col = 0; col < m.size; ++col) {
      const float x = (float(col) + 0.5f) / float(m.size) * 2.0f - 1.0f;
      const float y = 1.0f - (float(row) + 0.5f) / float(m.size) * 2.0f;
      const glm::dvec3 w0 = glm::dvec3(glm::vec3(inv * glm::vec4(x, y, 0.0f, 1.0f))) + m.origin;
      const glm::dvec3 w1 = glm::dvec3(glm::vec3(inv * glm::vec4(x, y, 1.0f, 1.0f))) + m.origin;
      double lo = 0.0, hi = 1.0;
      auto slab = [&](double a, double b, double mn, double mx) {
        const double d = b - a;
        if (std::abs(d) < 1e-12) {
          if (a < mn || a > mx) hi = -1.0;
          return;
        }
        double t0 = (mn - a) / d, t1 = (mx - a) / d;
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
      };
      slab(w0.x, w1.x, -1.0, 1.0);
      slab(w0.y, w1.y, 0.0, double(wall_height));
      m.depth[size_t(row) * m.size + col] = hi >= lo ? float(hi) : 0.0f;
    }
  return m;
}

}  // namespace cr

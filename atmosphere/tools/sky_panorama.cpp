#include "atmosphere/tools/sky_panorama.h"

#include <algorithm>
#include <cmath>

#include "engine/core/math_constants.h"

namespace cr {

std::vector<glm::vec3> panorama(int width, int height, double top_deg, double bottom_deg) {
  std::vector<glm::vec3> d(size_t(width) * height);
  for (int y = 0; y < height; ++y) {
    const double e = (top_deg - (y + 0.5) / height * (top_deg - bottom_deg)) * kPiD / 180.0;
    for (int x = 0; x < width; ++x) {
      const double a = 2.0 * kPiD * (x + 0.5) / width;
      d[size_t(y) * width + x] = glm::vec3(float(std::cos(e) * std::cos(a)), float(std::sin(e)),
                                           float(std::cos(e) * std::sin(a)));
    }
  }
  return d;
}

std::vector<glm::vec3> accuracy_panorama(int width, int height, bool from_space) {
  return from_space ? panorama(width, height, 0.0, -90.0) : panorama(width, height, 90.0, -10.0);
}

std::vector<bool> scored_sky(const SkyFrame& frame, const std::vector<glm::vec3>& dirs, bool from_space) {
  std::vector<bool> sky(dirs.size());
  const float mu_top =
      -float(std::sqrt(std::max(0.0, 1.0 - std::pow(frame.model.top_radius / frame.camera_radius, 2))));
  for (size_t i = 0; i < dirs.size(); ++i) {
    const float mu = glm::dot(dirs[i], glm::vec3(0, 1, 0));
    sky[i] = from_space ? mu < mu_top : mu > frame.mu_horizon;
  }
  return sky;
}

}  // namespace cr

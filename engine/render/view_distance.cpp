#include "engine/render/view_distance.h"

#include <cmath>
#include <limits>

namespace cr {

namespace {

// 1 + s^2 for the ray's screen coordinate s along one axis.
inline float ray_term(float s) { return 1.0f + s * s; }

inline float distance_at(const Camera& cam, float depth, float one_plus_sx2, float sy2) {
  if (!(depth > 0.0f)) return std::numeric_limits<float>::infinity();
  if (cam.orthographic) return cam.view_depth(depth);  // parallel rays: the distance is the view depth
  return cam.znear / depth * std::sqrt(one_plus_sx2 + sy2);
}

}  // namespace

float view_distance(const Camera& cam, int w, int h, float px, float py, float depth) {
  return view_distance(cam, PixelRays(cam, w, h), px, py, depth);
}

float view_distance(const Camera& cam, const PixelRays& rays, float px, float py, float depth) {
  const float sy = rays.screen_y(py);
  return distance_at(cam, depth, ray_term(rays.screen_x(px)), sy * sy);
}

void view_distances(const Camera& cam, int w, int h, const std::vector<float>& depth, std::vector<float>& distance,
                    JobSystem& jobs) {
  const PixelRays rays(cam, w, h);
  std::vector<float> sx2(static_cast<size_t>(w));
  for (int x = 0; x < w; ++x) sx2[size_t(x)] = ray_term(rays.screen_x(float(x) + 0.5f));
  jobs.parallel_for("depth", size_t(h), 8, [&](size_t y0, size_t y1) {
    for (size_t y = y0; y < y1; ++y) {
      const float sy = rays.screen_y(float(y) + 0.5f);
      const float sy2 = sy * sy;
      const size_t row = y * size_t(w);
      for (int x = 0; x < w; ++x) distance[row + size_t(x)] = distance_at(cam, depth[row + size_t(x)], sx2[size_t(x)], sy2);
    }
  });
}

}  // namespace cr

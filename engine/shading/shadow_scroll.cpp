// Scrolling the sun's shadow map (shadow_scroll.h).
#include "engine/shading/shadow_scroll.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace cr {

ShadowUpdate plan_shadow_update(const ShadowMap& last, const ShadowFit& fit, int pcf_radius, double depth_margin) {
  ShadowUpdate u;
  const int64_t dx = fit.grid_x - last.grid_x, dy = fit.grid_y - last.grid_y;
  // The fit's depth interval, measured from last's depth origin.
  const double shift = fit.centre_depth - last.origin_depth;
  const bool same_grid = fit.size > 0 && last.size == fit.size && last.texel_world_size == float(fit.texel) &&
                         last.direction_to_sun == glm::vec3(fit.axis_z) && last.pcf_radius == std::max(pcf_radius, 0);
  if (same_grid && std::llabs(dx) < fit.size && std::llabs(dy) < fit.size && fit.need_min + shift >= last.depth_min &&
      fit.need_max + shift <= last.depth_max) {
    u.map = shadow_projection(fit, pcf_radius, last.origin_depth, last.depth_min, last.depth_max);
    u.scroll = true;
    u.dx = int(dx);
    u.dy = int(dy);
    return u;
  }
  u.map = shadow_projection(fit, pcf_radius, fit.centre_depth, fit.need_min - depth_margin,
                            fit.need_max + depth_margin);
  return u;
}

void scroll_depth(JobSystem& jobs, const std::vector<float>& from, int size, int dx, int dy, std::vector<float>& to) {
  to.resize(size_t(size) * size_t(size));
  // Columns [c0, c1) of a new row come from old columns [c0 + dx, c1 + dx).
  const int c0 = std::max(0, -dx), c1 = std::min(size, size - dx);
  jobs.parallel_for("shadow.scroll", size_t(size), 64, [&](size_t begin, size_t end) {
    for (size_t row = begin; row < end; ++row) {
      const int old_row = int(row) - dy;
      if (old_row < 0 || old_row >= size || c1 <= c0) continue;  // a row that comes into view
      std::memcpy(&to[row * size_t(size) + size_t(c0)], &from[size_t(old_row) * size_t(size) + size_t(c0 + dx)],
                  size_t(c1 - c0) * sizeof(float));
    }
  });
}

std::vector<PixelRect> exposed_texels(int size, int dx, int dy) {
  std::vector<PixelRect> rects;
  const int last = size - 1;
  if (dx > 0) rects.push_back({std::max(size - dx, 0), 0, last, last});
  if (dx < 0) rects.push_back({0, 0, std::min(-dx, size) - 1, last});
  if (dy > 0) rects.push_back({0, 0, last, std::min(dy, size) - 1});
  if (dy < 0) rects.push_back({0, std::max(size + dy, 0), last, last});
  return rects;
}

std::vector<PixelRect> exposed_tiles(int size, int tile_size, int dx, int dy) {
  std::vector<PixelRect> rects = exposed_texels(size, dx, dy);
  for (PixelRect& r : rects) {
    r.x0 -= r.x0 % tile_size;
    r.y0 -= r.y0 % tile_size;
    r.x1 = std::min(size - 1, r.x1 - r.x1 % tile_size + tile_size - 1);
    r.y1 = std::min(size - 1, r.y1 - r.y1 % tile_size + tile_size - 1);
  }
  return rects;
}

glm::mat4 region_projection(const ShadowMap& map, const PixelRect& rect) {
  // Columns [x0, x1 + 1) span NDC x from 2 x0 / size - 1; rows run down from y = 1.
  const double s = 2.0 / double(map.size);
  const double x0 = (rect.x0 - 1) * s - 1.0, x1 = (rect.x1 + 2) * s - 1.0;
  const double y0 = 1.0 - (rect.y1 + 2) * s, y1 = 1.0 - (rect.y0 - 1) * s;
  glm::dmat4 to_region(1.0);
  to_region[0][0] = 2.0 / (x1 - x0);
  to_region[1][1] = 2.0 / (y1 - y0);
  to_region[3][0] = -(x1 + x0) / (x1 - x0);
  to_region[3][1] = -(y1 + y0) / (y1 - y0);
  return glm::mat4(to_region * glm::dmat4(map.light_view_proj));
}

}  // namespace cr

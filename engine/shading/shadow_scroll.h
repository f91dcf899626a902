#pragma once
// Scrolling the sun's shadow map with a moving camera.
//
// The map's texel grid is fixed in the light's view (shadow_map.h), so a
// camera that moves or turns under a still sun moves the map by whole
// texels: last frame's depth image, shifted, holds the same depths (up to
// float rounding of the projection) everywhere but the strips that come
// into view, and only those render. That needs the depth values to keep
// their meaning: a scrolled map keeps the depth origin and interval of the
// map it scrolls from, which is why a map that will scroll is rendered
// with a depth margin, so the view can move along the light's axis too.
#include <vector>

#include "engine/core/job_system.h"
#include "engine/raster/triangle_setup.h"
#include "engine/shading/shadow_map.h"

namespace cr {

struct ShadowUpdate {
  ShadowMap map;        // this frame's projection, with an empty depth image
  bool scroll = false;  // the map is `last` moved by (dx, dy) texels
  int dx = 0, dy = 0;   // new column = old column - dx, new row = old row + dy
};

// This frame's projection for `fit` given last frame's map: `last` scrolled
// when it has the same size, texel, sun and PCF radius, moves by less than
// its size and its depth interval covers the fit's; else a new projection
// around the fit, its depth interval widened by `depth_margin` metres at
// either end.
ShadowUpdate plan_shadow_update(const ShadowMap& last, const ShadowFit& fit, int pcf_radius, double depth_margin);

// `to` (resized to size^2) = `from`'s depth image moved by (dx, dy) texels;
// the texels that come into view are left for the caller to render.
void scroll_depth(JobSystem& jobs, const std::vector<float>& from, int size, int dx, int dy, std::vector<float>& to);

// The texels of a size x size map scrolled by (dx, dy) that come into view:
// up to two rectangles (a band of columns and one of rows), none when it did
// not move.
std::vector<PixelRect> exposed_texels(int size, int dx, int dy);

// exposed_texels grown to whole tiles of `tile_size`: what renders again
// (the rasterizer renders whole tiles) and so what the casters must cover.
std::vector<PixelRect> exposed_tiles(int size, int tile_size, int dx, int dy);

// The map's clip transform with `rect`'s texels (grown by one texel for
// rounding) mapped to x, y in [-1, 1]: aabb_in_ortho with it culls the
// casters that cannot touch the rectangle.
glm::mat4 region_projection(const ShadowMap& map, const PixelRect& rect);

}  // namespace cr

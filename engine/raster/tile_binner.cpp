#include "engine/raster/tile_binner.h"

#include <algorithm>
#include <bit>

#include "engine/core/error.h"

namespace cr {

TileGrid TileGrid::make(int width, int height, int tile_size) {
  if (tile_size < 8 || tile_size > 256 || !std::has_single_bit(unsigned(tile_size)))
    throw Error("rasterizer: tile size " + std::to_string(tile_size) + " is not a power of two in [8, 256]");
  TileGrid g;
  g.width = width;
  g.height = height;
  g.tile_size = tile_size;
  g.tile_shift = std::countr_zero(unsigned(tile_size));
  g.tiles_x = (width + tile_size - 1) >> g.tile_shift;
  g.tiles_y = (height + tile_size - 1) >> g.tile_shift;
  return g;
}

PixelRect TileGrid::tile_rect(int tile) const {
  const int x0 = (tile % tiles_x) << tile_shift, y0 = (tile / tiles_x) << tile_shift;
  return {x0, y0, std::min(x0 + tile_size, width) - 1, std::min(y0 + tile_size, height) - 1};
}

namespace {

// Calls fn(tile) for each tile that triangle i may cover, in row-major order.
template <typename Fn>
void for_each_tile(const SetupBatch& setup, uint32_t i, const TileGrid& grid, int32_t margin, Fn&& fn) {
  const PixelRect& r = setup.bounds[i];
  const int tx0 = r.x0 >> grid.tile_shift, tx1 = r.x1 >> grid.tile_shift;
  const int ty0 = r.y0 >> grid.tile_shift, ty1 = r.y1 >> grid.tile_shift;
  if (tx0 == tx1 && ty0 == ty1) {
    fn(ty0 * grid.tiles_x + tx0);
    return;
  }
  // Spanning several tiles: skip tiles of the bounding box the triangle misses
  // (long diagonal slivers), testing its edges at the tile's extreme pixels,
  // or a tiny triangle's covered pixels.
  const ScreenTriangle& t = setup.triangles[i];
  for (int ty = ty0; ty <= ty1; ++ty)
    for (int tx = tx0; tx <= tx1; ++tx) {
      const int tile = ty * grid.tiles_x + tx;
      const PixelRect part = intersect(r, grid.tile_rect(tile));
      if (t.tiny ? tiny_mask_within(t.mask, r, part) != 0 : may_cover(t, part, margin)) fn(tile);
    }
}

}  // namespace

void bin_triangles(const SetupBatch& setup, const TileGrid& grid, int32_t sample_margin, TileBins& bins) {
  const uint32_t n = uint32_t(setup.triangles.size());
  // Counting sort by tile: count, prefix sums, then scatter in triangle order
  // (begin[t + 1] serves as tile t's cursor and ends at its final value).
  bins.begin.assign(size_t(grid.tile_count()) + 2, 0);
  for (uint32_t i = 0; i < n; ++i) for_each_tile(setup, i, grid, sample_margin, [&](int tile) { ++bins.begin[tile + 2]; });
  for (int t = 0; t < grid.tile_count(); ++t) bins.begin[t + 2] += bins.begin[t + 1];
  bins.items.resize(bins.begin[grid.tile_count() + 1]);
  for (uint32_t i = 0; i < n; ++i) for_each_tile(setup, i, grid, sample_margin, [&](int tile) { bins.items[bins.begin[tile + 1]++] = i; });
  bins.begin.pop_back();
}

}  // namespace cr

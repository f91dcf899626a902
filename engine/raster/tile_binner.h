#pragma once
// Binning of screen triangles into square tiles. Each chunk of set-up
// triangles gets its own per-tile lists (a counting sort by tile, stable), so
// chunks bin in parallel; a tile then walks the chunks in order and sees its
// triangles in exact submission order, whatever the thread count.
#include <cstdint>
#include <vector>

#include "engine/raster/triangle_setup.h"

namespace cr {

struct TileGrid {
  int width = 0;
  int height = 0;
  int tile_size = 0;   // power of two
  int tile_shift = 0;  // log2(tile_size)
  int tiles_x = 0;
  int tiles_y = 0;

  static TileGrid make(int width, int height, int tile_size);
  int tile_count() const { return tiles_x * tiles_y; }
  PixelRect tile_rect(int tile) const;  // clamped to the image
};

// Per-tile lists of one chunk: triangles of tile t are
// items[begin[t]] .. items[begin[t + 1] - 1], indices into its SetupBatch.
struct TileBins {
  std::vector<uint32_t> begin;
  std::vector<uint32_t> items;
};

// A chunk of the geometry pipeline: set-up triangles and their tile lists.
struct GeometryChunk {
  SetupBatch setup;
  TileBins bins;
};

// sample_margin: the setup's (SetupParams::sample_margin).
void bin_triangles(const SetupBatch& setup, const TileGrid& grid, int32_t sample_margin, TileBins& bins);

}  // namespace cr

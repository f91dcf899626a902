#pragma once
// Rasterisation of one screen tile: every triangle binned to the tile, in
// submission order (one job per tile, so every output pixel has exactly one
// writer).
//
// A tiny triangle (one sample per pixel, pixel bounds within 8x8) had its
// covered pixel centres found at setup (ScreenTriangle::mask; one that covers
// none was not emitted), so only its depth is evaluated, one span per row.
// A small triangle (vertex extent <= 64 pixels, the common case) has all its
// edge values in int32 and is scanned row by row over its box, 8 pixels per
// span (span8.h: one AVX2 register, or two SSE2). A larger one is walked in
// 8x8 blocks, each classifying the edges in int64 at its corners: an edge
// that excludes the block rejects it, one that includes it is dropped (a
// block inside all three is filled without edge tests), and only crossing
// edges are evaluated per pixel.
// With one sample per pixel a tile is cleared and rasterised in place in the
// image; a span that would cross the tile's right edge is moved left to end
// there, its extra columns masked, so a job never touches another tile's
// pixels. Tiles narrower than a span and multisampled ones use a tile
// buffer with padded rows instead (one layer per sample).
// Depth is float reversed-Z with an early GREATER test; alpha-mask coverage
// is asked only for samples that pass it. Everything a pixel sees is a pure
// function of the pixel and the triangle, so results do not depend on the
// tile size or on which thread runs the tile.
//
// Multisampled visibility (a pattern of 2-8 samples): each sample is a
// tile-local layer of its own, rasterised as the triangle shifted by minus
// the sample's offset, with the edge constants recomputed exactly from
// ScreenTriangle::c_num and the depth plane moved to the sample; alpha-mask
// coverage is asked at each sample's own position. While the layers are in
// cache the tile is resolved: a pixel whose samples all see one triangle
// gets its id and its samples' mean depth in the image, any other is listed
// with all its samples (MixedSamples) and gets its first sample's.
// Multisampled blending tests each sample against the pixel's one opaque
// depth and delivers one fragment per pixel and triangle, at the centroid of
// the samples that passed, their share as coverage.
#include <cstdint>
#include <span>

#include "engine/core/depth_format.h"
#include "engine/raster/raster_types.h"
#include "engine/raster/sample_pattern.h"
#include "engine/raster/tile_binner.h"

namespace cr {

enum class TileMode : uint8_t {
  Visibility,  // depth + triangle id, written
  Depth,       // depth only, written
  Blended,     // depth tested (not written), fragments delivered to a callback
};

struct TileTarget {
  TileMode mode = TileMode::Visibility;
  int stride = 0;                        // image row length in pixels
  float* depth = nullptr;                // image depth, written (Visibility, Depth)
  uint32_t* ids = nullptr;               // image triangle ids, written (Visibility)
  const float* opaque_depth = nullptr;   // image depth tested against (Blended)
  const CoverageFn* coverage = nullptr;  // for alpha-mask triangles (Visibility, Depth)
  const FragmentFn* fragment = nullptr;  // Blended
  SamplePattern pattern;                 // Visibility, Blended: samples per pixel (else 1)
  MixedSamples* mixed = nullptr;         // Visibility with several samples: this tile's mixed pixels
  DepthFormat depth_format = DepthFormat::Float32;  // each sample's depth rounded to it before test and store
};

void raster_tile(int tile, const TileGrid& grid, std::span<const GeometryChunk> chunks, const TileTarget& target,
                 TileStats& stats);

}  // namespace cr

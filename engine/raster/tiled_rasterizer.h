#pragma once
// The tiled visibility-buffer rasterizer.
//
// Pipeline per render call, each stage a parallel_for on the job system:
//   "vertex"  positions -> clip space (float model_to_clip per draw)
//   "setup"   cull, clip (near, guard band), snap, edge functions; chunks of
//             kSetupChunk input triangles, each chunk with its own output
//   "bin"     per chunk, per-tile triangle lists (submission order kept)
//   "raster"  one job per tile: all its triangles in submission order
// The output is bit-identical for any thread count and any tile size.
//
// Triangle ids: every original triangle that survives culling gets an id,
// shared by all pieces the clipper cuts from it; the visibility buffer, the
// callbacks and the queries use it. Ids stay valid until the next render call
// of the same kind (visibility, blended, depth each keep their own geometry).
// The queries (barycentrics, ref, interp) answer for the ids the rasterizer
// reports: a tiny triangle that covers no pixel centre keeps its id but is
// reported nowhere, and its interpolation planes are never computed.
//
// One instance per view: calls on one instance must not overlap; render the
// shadow map with its own instance if it runs concurrently with the view.
// The object keeps its buffers between frames, so steady-state frames do not
// allocate.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"
#include "engine/raster/barycentrics.h"
#include "engine/raster/raster_types.h"
#include "engine/raster/sample_pattern.h"
#include "engine/raster/tile_binner.h"
#include "engine/raster/tile_raster.h"
#include "engine/raster/triangle_interp.h"

namespace cr {

// Per pixel: nearest opaque or alpha-masked surface. Row-major, y down.
// With several samples per pixel, a pixel whose samples all see one triangle
// holds it and their mean depth; the others (edges) are listed per tile in
// `mixed` with every sample, and hold their first sample.
struct VisibilityBuffer {
  int width = 0;
  int height = 0;
  SamplePattern pattern;           // sample positions (1: the pixel centre)
  TileGrid grid;                   // the tiles `mixed` is listed by
  std::vector<float> depth;        // reversed-Z NDC depth; 0 = nothing drawn
  DepthFormat depth_format = DepthFormat::Float32;  // the values of `depth` are of this format
  std::vector<uint32_t> triangle;  // triangle id; kNoTriangle = nothing drawn
  std::vector<MixedSamples> mixed;  // per tile (row-major tiles); empty with one sample

  size_t index(int x, int y) const { return size_t(y) * width + x; }
  // Sample s of pixel (x, y): its triangle id and depth.
  uint32_t sample_triangle(int x, int y, int s) const;
  float sample_depth(int x, int y, int s) const;

 private:
  // Position of pixel (x, y) in its tile's mixed list, or -1.
  ptrdiff_t mixed_slot(int x, int y, const MixedSamples*& tile) const;
};

class TiledRasterizer {
 public:
  // Input triangles per setup chunk (a power of two; part of the id encoding).
  static constexpr uint32_t kSetupChunk = 1024;

  // Opaque and alpha-mask draws into the visibility buffer (cleared first),
  // at `samples` (1, 2, 4, 8) samples per pixel (sample_pattern.h).
  // Back faces of single-sided draws are culled. `coverage` is required when
  // a draw has alpha_mask; it may be called concurrently for different
  // pixels, at each sample's position.
  // Each sample's depth is rounded to `depth_format` before the test and the
  // store (render_blended's test uses the same format).
  const RasterStats& render_visibility(JobSystem& jobs, int width, int height, int tile_size,
                                       std::span<const RasterDraw> draws, const CoverageFn& coverage = {},
                                       int samples = 1, DepthFormat depth_format = DepthFormat::Float32);
  const VisibilityBuffer& visibility() const { return visibility_; }

  // Blended draws, given back to front (see blend_order.h), at the samples of
  // the last render_visibility, tested against `opaque_depth` (one value per
  // pixel; empty: the last render_visibility's), not written. `fragment` is
  // called once per pixel and triangle some sample of it passes, in primitive
  // order per pixel, with the share of samples it covers; concurrently for
  // different tiles, so it must only touch pixel (x, y).
  // alpha_mask is ignored here: blending uses the alpha itself.
  const RasterStats& render_blended(JobSystem& jobs, std::span<const RasterDraw> back_to_front,
                                    const FragmentFn& fragment, std::span<const float> opaque_depth = {});

  // Depth only into `depth` (resized to size * size, row-major, 0 = empty),
  // for shadow maps with an orthographic matrix (clip z in [0, 1], 1 nearest).
  // Nothing is culled: terrain and other open meshes have no back faces to
  // cast from, and the shadow lookup's normal-offset and slope biases handle
  // the acne that rendering front faces invites.
  // With `regions`, only the tiles that overlap one render (each whole, so
  // a region's texels equal a full render's); the others keep their values.
  const RasterStats& render_depth(JobSystem& jobs, int size, int tile_size, std::span<const RasterDraw> draws,
                                  std::vector<float>& depth, const CoverageFn& coverage = {},
                                  std::span<const PixelRect> regions = {});

  // Perspective-correct barycentrics of the original triangle at screen
  // position (px, py) (pixel centre = x + 0.5), with d/dx and d/dy per pixel.
  Barycentrics barycentrics(uint32_t triangle_id, float px, float py) const;
  TriangleRef ref(uint32_t triangle_id) const;
  // The interpolation planes behind barycentrics(): a caller shading many
  // pixels of one triangle looks them up once and calls interpolate() inline.
  const TriangleInterp& interp(uint32_t triangle_id) const;

 private:
  struct Geometry {
    std::vector<ProjectedVertex> vertices;
    std::vector<size_t> vertex_begin;    // per draw, + total
    std::vector<size_t> triangle_begin;  // per draw, + total
    std::vector<GeometryChunk> chunks;   // grows only; the first chunk_count are live
    size_t chunk_count = 0;
    RasterStats stats;
  };
  enum GeometrySet : uint32_t { kOpaque = 0, kBlended = 1, kDepth = 2, kSetCount = 3 };

  void build(JobSystem& jobs, GeometrySet set, std::span<const RasterDraw> draws, const TileGrid& grid,
             CullMode cull, int32_t sample_margin = 0);
  // Every tile, or only those listed in `tiles`.
  void raster(JobSystem& jobs, GeometrySet set, const TileGrid& grid, const TileTarget& target,
              std::span<MixedSamples> mixed = {}, std::span<const uint32_t> tiles = {});

  Geometry geometry_[kSetCount];
  std::vector<uint32_t> region_tiles_;  // render_depth's tiles within its regions
  TileGrid visibility_grid_;
  VisibilityBuffer visibility_;
};

}  // namespace cr

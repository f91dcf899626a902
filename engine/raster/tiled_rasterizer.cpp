#include "engine/raster/tiled_rasterizer.h"

#include <algorithm>
#include <string>

#include "engine/core/error.h"

namespace cr {

namespace {

// Triangle id = set << 30 | chunk << 10 | index within the chunk's survivors.
constexpr uint32_t kSetShift = 30;
constexpr uint32_t kChunkShift = 10;
static_assert(TiledRasterizer::kSetupChunk == 1u << kChunkShift);
constexpr size_t kMaxTriangles = size_t(1) << kSetShift;
constexpr size_t kVertexGrain = 4096;

void check_image_size(int width, int height) {
  if (width < 1 || height < 1 || width > kMaxImageSize || height > kMaxImageSize)
    throw Error("rasterizer: image size " + std::to_string(width) + "x" + std::to_string(height) +
                " outside [1, " + std::to_string(kMaxImageSize) + "]");
}

void check_coverage(std::span<const RasterDraw> draws, const CoverageFn& coverage) {
  for (const RasterDraw& d : draws)
    if (d.alpha_mask && !coverage)
      throw Error("rasterizer: draw " + std::to_string(d.draw_index) + " is alpha-masked but no coverage function was given");
}

}  // namespace

void TiledRasterizer::build(JobSystem& jobs, GeometrySet set, std::span<const RasterDraw> draws, const TileGrid& grid,
                            CullMode cull, int32_t sample_margin) {
  Geometry& g = geometry_[set];
  g.vertex_begin.assign(1, 0);
  g.triangle_begin.assign(1, 0);
  for (const RasterDraw& d : draws) {
    if (!d.primitive) throw Error("rasterizer: draw " + std::to_string(d.draw_index) + " has no primitive");
    g.vertex_begin.push_back(g.vertex_begin.back() + d.primitive->positions.size());
    g.triangle_begin.push_back(g.triangle_begin.back() + d.primitive->triangle_count());
  }
  const size_t vertex_count = g.vertex_begin.back(), triangle_count = g.triangle_begin.back();
  if (triangle_count >= kMaxTriangles)
    throw Error("rasterizer: " + std::to_string(triangle_count) + " triangles in one pass exceed the limit of " +
                std::to_string(kMaxTriangles));

  SetupParams params;
  params.width = grid.width;
  params.height = grid.height;
  params.band = GuardBand::for_image(grid.width, grid.height, kGuardBandPixels);
  params.cull = cull;
  params.sample_margin = sample_margin;
  params.sx = 2.0 / params.width;
  params.sy = -2.0 / params.height;

  g.vertices.resize(vertex_count);
  jobs.parallel_for("vertex", vertex_count, kVertexGrain, [&](size_t begin, size_t end) {
    // The chunk's part of each draw it overlaps.
    size_t d = size_t(std::upper_bound(g.vertex_begin.begin(), g.vertex_begin.end(), begin) - g.vertex_begin.begin()) - 1;
    for (size_t v = begin; v < end; ++d) {
      const size_t draw_end = std::min<size_t>(end, g.vertex_begin[d + 1]);
      if (draw_end == v) continue;  // a draw without vertices
      project_vertices(&draws[d].primitive->positions[v - g.vertex_begin[d]], draw_end - v, draws[d].model_to_clip,
                       params, &g.vertices[v]);
      v = draw_end;
    }
  });

  g.chunk_count = (triangle_count + kSetupChunk - 1) / kSetupChunk;
  if (g.chunks.size() < g.chunk_count) g.chunks.resize(g.chunk_count);
  jobs.parallel_for("setup", triangle_count, kSetupChunk, [&](size_t begin, size_t end) {
    const size_t chunk = begin / kSetupChunk;
    SetupBatch& out = g.chunks[chunk].setup;
    out.clear(uint32_t(set) << kSetShift | uint32_t(chunk) << kChunkShift);
    // The chunk's part of each draw it overlaps.
    size_t d = size_t(std::upper_bound(g.triangle_begin.begin(), g.triangle_begin.end(), begin) - g.triangle_begin.begin()) - 1;
    for (size_t tri = begin; tri < end; ++d) {
      const size_t draw_end = std::min<size_t>(end, g.triangle_begin[d + 1]);
      if (draw_end == tri) continue;  // a draw without triangles
      const RasterDraw& draw = draws[d];
      setup_triangles(&g.vertices[g.vertex_begin[d]], draw.primitive->positions.size(), draw,
                      uint32_t(tri - g.triangle_begin[d]), uint32_t(draw_end - tri), params, out);
      tri = draw_end;
    }
  });

  jobs.parallel_for("bin", g.chunk_count, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) bin_triangles(g.chunks[c].setup, grid, sample_margin, g.chunks[c].bins);
  });

  RasterStats& s = g.stats;
  s = {};
  s.triangles_in = triangle_count;
  for (size_t c = 0; c < g.chunk_count; ++c) {
    const GeometryChunk& chunk = g.chunks[c];
    s.triangles_culled += chunk.setup.counters.culled;
    s.triangles_clipped += chunk.setup.counters.clipped;
    s.triangles_visible += chunk.setup.counters.visible;
    s.screen_triangles += chunk.setup.counters.screen;
    s.tile_triangle_pairs += chunk.bins.items.size();
  }
}

void TiledRasterizer::raster(JobSystem& jobs, GeometrySet set, const TileGrid& grid, const TileTarget& target,
                             std::span<MixedSamples> mixed, std::span<const uint32_t> tiles) {
  Geometry& g = geometry_[set];
  RasterStats& s = g.stats;
  s.tiles_x = grid.tiles_x;
  s.tiles_y = grid.tiles_y;
  s.tiles.assign(size_t(grid.tile_count()), TileStats{});
  const std::span<const GeometryChunk> chunks(g.chunks.data(), g.chunk_count);
  const size_t count = tiles.empty() ? size_t(grid.tile_count()) : tiles.size();
  jobs.parallel_for("raster", count, 1, [&](size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) {
      const size_t t = tiles.empty() ? k : size_t(tiles[k]);
      TileTarget tile_target = target;
      if (!mixed.empty()) tile_target.mixed = &mixed[t];
      raster_tile(int(t), grid, chunks, tile_target, s.tiles[t]);
    }
  });
  for (const TileStats& t : s.tiles) {
    s.pixels_covered += t.pixels_covered;
    s.pixels_passed += t.pixels_passed;
  }
}

const RasterStats& TiledRasterizer::render_visibility(JobSystem& jobs, int width, int height, int tile_size,
                                                      std::span<const RasterDraw> draws, const CoverageFn& coverage,
                                                      int samples, DepthFormat depth_format) {
  check_image_size(width, height);
  check_coverage(draws, coverage);
  const TileGrid grid = TileGrid::make(width, height, tile_size);
  visibility_grid_ = TileGrid{};  // invalid until the pass completes
  visibility_.width = width;
  visibility_.height = height;
  visibility_.pattern = sample_pattern(samples);
  visibility_.grid = grid;
  visibility_.depth_format = depth_format;
  visibility_.depth.resize(size_t(width) * height);
  visibility_.triangle.resize(size_t(width) * height);
  visibility_.mixed.resize(samples > 1 ? size_t(grid.tile_count()) : 0);
  build(jobs, kOpaque, draws, grid, CullMode::Back, visibility_.pattern.margin_subpixels());
  TileTarget target;
  target.mode = TileMode::Visibility;
  target.stride = width;
  target.depth = visibility_.depth.data();
  target.ids = visibility_.triangle.data();
  target.coverage = &coverage;
  target.pattern = visibility_.pattern;
  target.depth_format = depth_format;
  raster(jobs, kOpaque, grid, target, visibility_.mixed);
  visibility_grid_ = grid;
  return geometry_[kOpaque].stats;
}

const RasterStats& TiledRasterizer::render_blended(JobSystem& jobs, std::span<const RasterDraw> back_to_front,
                                                   const FragmentFn& fragment, std::span<const float> opaque_depth) {
  if (visibility_grid_.tile_count() == 0)
    throw Error("rasterizer: render_blended needs the depth of a completed render_visibility");
  if (!fragment) throw Error("rasterizer: render_blended needs a fragment function");
  const size_t pixels = visibility_.depth.size();
  if (!opaque_depth.empty() && opaque_depth.size() != pixels)
    throw Error("rasterizer: render_blended's opaque depth has " + std::to_string(opaque_depth.size()) +
                " values for " + std::to_string(pixels) + " pixels");
  build(jobs, kBlended, back_to_front, visibility_grid_, CullMode::Back, visibility_.pattern.margin_subpixels());
  TileTarget target;
  target.mode = TileMode::Blended;
  target.pattern = visibility_.pattern;
  target.stride = visibility_.width;
  target.opaque_depth = opaque_depth.empty() ? visibility_.depth.data() : opaque_depth.data();
  target.fragment = &fragment;
  target.depth_format = visibility_.depth_format;
  raster(jobs, kBlended, visibility_grid_, target);
  return geometry_[kBlended].stats;
}

const RasterStats& TiledRasterizer::render_depth(JobSystem& jobs, int size, int tile_size,
                                                 std::span<const RasterDraw> draws, std::vector<float>& depth,
                                                 const CoverageFn& coverage, std::span<const PixelRect> regions) {
  check_image_size(size, size);
  check_coverage(draws, coverage);
  const TileGrid grid = TileGrid::make(size, size, tile_size);
  depth.resize(size_t(size) * size);
  region_tiles_.clear();
  for (int t = 0; !regions.empty() && t < grid.tile_count(); ++t) {
    const PixelRect rect = grid.tile_rect(t);
    for (const PixelRect& r : regions)
      if (!intersect(rect, r).empty()) {
        region_tiles_.push_back(uint32_t(t));
        break;
      }
  }
  if (!regions.empty() && region_tiles_.empty()) {  // nothing to render
    geometry_[kDepth].stats = {};
    return geometry_[kDepth].stats;
  }
  build(jobs, kDepth, draws, grid, CullMode::None);
  TileTarget target;
  target.mode = TileMode::Depth;
  target.stride = size;
  target.depth = depth.data();
  target.coverage = &coverage;
  raster(jobs, kDepth, grid, target, {}, region_tiles_);
  return geometry_[kDepth].stats;
}

ptrdiff_t VisibilityBuffer::mixed_slot(int x, int y, const MixedSamples*& tile) const {
  if (mixed.empty()) return -1;
  tile = &mixed[size_t((y >> grid.tile_shift) * grid.tiles_x + (x >> grid.tile_shift))];
  const uint32_t pixel = uint32_t(index(x, y));
  const auto it = std::lower_bound(tile->pixels.begin(), tile->pixels.end(), pixel);
  return it != tile->pixels.end() && *it == pixel ? it - tile->pixels.begin() : -1;
}

uint32_t VisibilityBuffer::sample_triangle(int x, int y, int s) const {
  const MixedSamples* tile = nullptr;
  const ptrdiff_t k = mixed_slot(x, y, tile);
  return k < 0 ? triangle[index(x, y)] : tile->triangle[size_t(k) * size_t(pattern.count) + size_t(s)];
}

float VisibilityBuffer::sample_depth(int x, int y, int s) const {
  const MixedSamples* tile = nullptr;
  const ptrdiff_t k = mixed_slot(x, y, tile);
  return k < 0 ? depth[index(x, y)] : tile->depth[size_t(k) * size_t(pattern.count) + size_t(s)];
}

const TriangleInterp& TiledRasterizer::interp(uint32_t triangle_id) const {
  const uint32_t set = triangle_id >> kSetShift;
  const uint32_t chunk = (triangle_id & ((1u << kSetShift) - 1)) >> kChunkShift;
  const uint32_t index = triangle_id & (kSetupChunk - 1);
  if (set >= kSetCount || chunk >= geometry_[set].chunk_count ||
      index >= geometry_[set].chunks[chunk].setup.interps.size())
    throw Error("rasterizer: unknown triangle id " + std::to_string(triangle_id));
  return geometry_[set].chunks[chunk].setup.interps[index];
}

Barycentrics TiledRasterizer::barycentrics(uint32_t triangle_id, float px, float py) const {
  return interpolate(interp(triangle_id), px, py);
}

TriangleRef TiledRasterizer::ref(uint32_t triangle_id) const {
  const TriangleInterp& t = interp(triangle_id);
  return {t.draw_index, t.triangle_index, t.front_facing};
}

}  // namespace cr

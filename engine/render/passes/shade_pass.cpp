// "shade": every pixel once from its triangle id, then the edge fragments,
// in batches of runs of points on one triangle.
#include <algorithm>
#include <cstring>
#include <optional>

#include "engine/render/passes/engine_passes.h"
#include "engine/render/passes/surface_lookup.h"
#include "engine/shading/material_batch.h"
#include "engine/shading/shading_batch.h"
#include "engine/shading/surface_batch.h"

namespace cr {

namespace {

// Surfaces to shade, interpolated run by run (points on one triangle), then
// finished batch-wide, their materials evaluated and lit; where[k] names
// the pixel or fragment entry k belongs to.
struct ShadeQueue {
  SurfaceBatch surfaces;
  const Material* materials[SurfaceBatch::kCapacity];
  ShadingBatch batch;
  size_t where[SurfaceBatch::kCapacity];

  // Shades the queue and hands out(where[k], radiance) each point.
  template <class Out>
  void flush(const Scene& scene, float emissive_luminance, const SurfaceShader& shader, Out&& out) {
    surfaces.finish();
    evaluate_materials(scene, surfaces, materials, emissive_luminance, batch);
    shader.shade_batch(batch);
    for (int k = 0; k < batch.count; ++k) out(where[k], batch.radiance(k));
    surfaces.clear();
    batch.clear();
  }
};

// std::fill of a run of pixels, a few at a time: 16 pixels are 12 vector
// stores, where the compiler's loop stores 12 bytes one scalar at a time.
void fill_pixels(glm::vec3* out, int count, const glm::vec3& value) {
  constexpr int kChunk = 16;
  glm::vec3 chunk[kChunk];
  std::fill(chunk, chunk + kChunk, value);
  int k = 0;
  for (; k + kChunk <= count; k += kChunk) std::memcpy(out + k, chunk, sizeof chunk);
  std::fill(out + k, out + count, value);
}

// The triangles a band's pixels name, set up once each while they stay in a
// small direct-mapped table (neighbouring rows cross the same triangles).
class TriangleCache {
 public:
  struct Entry {
    uint32_t id = kNoTriangle;
    const Material* material = nullptr;
    const TriangleInterp* interp = nullptr;
    std::optional<TriangleSurface> surface;
  };
  struct Run {
    uint32_t id;
    int x, span;  // pixels x .. x + span - 1 of a row
  };
  TriangleCache(const SurfaceLookup& lookup, const TiledRasterizer& raster) : lookup_(lookup), raster_(raster) {}
  // Starts the memory loads that setting up the runs' uncached triangles
  // will wait on, all at once, so that their cache misses overlap (tiny
  // triangles: a new one every pixel or two) instead of coming one by one.
  void prefetch(const Run* runs, int count) const {
    for (int r = 0; r < count; ++r)
      if (!cached(runs[r].id)) lookup_.prefetch_plane(raster_, runs[r].id);
    for (int r = 0; r < count; ++r)
      if (!cached(runs[r].id)) lookup_.prefetch_indices(raster_.ref(runs[r].id));
    for (int r = 0; r < count; ++r)
      if (!cached(runs[r].id)) lookup_.prefetch_vertices(raster_.ref(runs[r].id));
  }
  const Entry& get(uint32_t id) {
    Entry& e = entries_[id % kSize];
    if (!cached(id)) {
      e.surface.emplace(lookup_.triangle(raster_, id, e.material));
      e.interp = &raster_.interp(id);
      e.id = id;
    }
    return e;
  }

 private:
  static constexpr uint32_t kSize = 128;
  bool cached(uint32_t id) const { return entries_[id % kSize].id == id; }
  const SurfaceLookup& lookup_;
  const TiledRasterizer& raster_;
  Entry entries_[kSize];
};

}  // namespace

void add_shade_pass(FrameGraph& graph, const FrameContext& ctx, const SurfaceLookup& surfaces_of,
                    const EngineResources& engine, EngineTargets& targets, bool fill_background,
                    uint64_t& pixels_shaded) {
  struct Data {
    FrameGraphId<Visibility> visibility;
    FrameGraphId<ShadowMap> shadow;
    FrameGraphId<LightEnvironment> light;
    FrameGraphId<FrameBuffers> color;
  };
  graph.add_pass<Data>("shade", [&](FrameGraph::Builder& b, Data& d) {
    d.visibility = b.read(targets.visibility);
    d.shadow = b.read(engine.shadow);
    d.light = b.read(engine.light);
    d.color = targets.color = b.write(targets.color);
  }, [ctx, &surfaces_of, fill_background, &pixels_shaded](const FrameGraph::Resources& r, const Data& d) {
    const Visibility& vis = r.get(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    const SurfaceShader shader = frame_shader(ctx, r.get(d.light), r.get(d.shadow));
    const float emissive = emissive_luminance(ctx.description);
    const int w = buffers.width, h = buffers.height;
    const std::vector<uint32_t>& ids = ctx.profile.msaa_samples == 1 ? vis.raster.visibility().triangle : vis.pixel_ids;
    // Without a sky plugin the background is the ambient radiance: a flat sky.
    const glm::vec3 background = ctx.description.ambient;
    // Jobs are bands of rows, walked in blocks a few pixels wide: a block's
    // rows mostly cross the same triangles, which the cache then sets up once.
    constexpr int kBandRows = 8, kBlockWidth = 64;
    std::vector<uint64_t> shaded_rows(size_t(h), 0);
    jobs.parallel_for("shade", size_t(h), kBandRows, [&](size_t y0, size_t y1) {
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      const Material** materials = q.materials;
      size_t* where = q.where;
      auto flush = [&] {
        q.flush(ctx.scene, emissive, shader,
                [&](size_t pixel, const glm::vec3& c) { buffers.color[pixel] = c; });
      };
      TriangleCache cache(surfaces_of, vis.raster);
      for (int bx = 0; bx < w; bx += kBlockWidth) {
        const int bx1 = std::min(w, bx + kBlockWidth);
        for (size_t y = y0; y < y1; ++y) {
          const uint32_t* row = &ids[y * size_t(w)];
          glm::vec3* color = &buffers.color[y * size_t(w)];
          // The segment's runs of pixels on one triangle; nothing drawn and
          // edge pixels (their fragments, below) both have the top bit set
          // and take the background, in runs.
          TriangleCache::Run runs[kBlockWidth];
          int run_count = 0;
          for (int x = bx; x < bx1;) {
            const uint32_t id = row[x];
            int end = x + 1;
            if (int32_t(id) < 0) {
              while (end < bx1 && int32_t(row[end]) < 0) ++end;
              if (fill_background) fill_pixels(color + x, end - x, background);
            } else {
              while (end < bx1 && row[end] == id) ++end;
              runs[run_count++] = {id, x, end - x};
            }
            x = end;
          }
          cache.prefetch(runs, run_count);
          uint64_t n = 0;
          for (int r = 0; r < run_count; ++r) {
            const TriangleCache::Entry& t = cache.get(runs[r].id);
            for (int x = runs[r].x, left = runs[r].span; left > 0;) {
              const int span = std::min(left, SurfaceBatch::kCapacity - surfaces.count);
              const size_t i = y * size_t(w) + size_t(x);
              for (int k = 0; k < span; ++k) {
                where[surfaces.count + k] = i + size_t(k);
                materials[surfaces.count + k] = t.material;
              }
              t.surface->add_span(surfaces, *t.interp, x, span, int(y));
              if (surfaces.full()) flush();
              x += span;
              left -= span;
            }
            n += uint64_t(runs[r].span);
          }
          shaded_rows[y] += n;
        }
      }
      if (surfaces.count > 0) flush();
    });
    // Edge pixels' fragments, each at its samples' centroid (inside its
    // triangle: no extrapolated attributes), in batches.
    std::vector<EdgeFragment>& fragments = buffers.fragments;
    const std::vector<size_t> chunks = fragment_chunks(fragments, 256);
    jobs.parallel_for("shade fragments", chunks.size() - 1, 1, [&](size_t c0, size_t c1) {
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      float px[SurfaceBatch::kCapacity], py[SurfaceBatch::kCapacity];
      auto flush = [&] {
        q.flush(ctx.scene, emissive, shader,
                [&](size_t f, const glm::vec3& c) { fragments[f].color = c; });
      };
      // A pixel's fragments lie on different triangles, its neighbours' on
      // the same ones: visiting the chunk's fragments by triangle gives runs
      // that share one triangle set-up. (Each point's shading is its own:
      // the order changes no result.)
      std::vector<std::pair<uint32_t, uint32_t>> order;  // (triangle, fragment)
      for (size_t f = chunks[c0]; f < chunks[c1]; ++f) {
        if (fragments[f].triangle == kNoTriangle)
          fragments[f].color = background;
        else
          order.emplace_back(fragments[f].triangle, uint32_t(f));
      }
      std::sort(order.begin(), order.end());
      std::optional<TriangleSurface> triangle;
      const Material* material = nullptr;
      for (size_t o = 0; o < order.size();) {
        const uint32_t id = order[o].first;
        triangle.emplace(surfaces_of.triangle(vis.raster, id, material));
        const TriangleInterp& interp = vis.raster.interp(id);
        while (o < order.size() && order[o].first == id) {
          const int room = SurfaceBatch::kCapacity - surfaces.count;
          int span = 0;
          for (; span < room && o + size_t(span) < order.size() && order[o + size_t(span)].first == id; ++span) {
            const size_t k = order[o + size_t(span)].second;
            q.where[surfaces.count + span] = k;
            q.materials[surfaces.count + span] = material;
            px[span] = fragments[k].x;
            py[span] = fragments[k].y;
          }
          triangle->add_points(surfaces, interp, px, py, span);
          if (surfaces.full()) flush();
          o += size_t(span);
        }
      }
      if (surfaces.count > 0) flush();
    });
    uint64_t total = 0;
    for (uint64_t n : shaded_rows) total += n;  // fixed-order reduction
    pixels_shaded = total;
  });
}

}  // namespace cr

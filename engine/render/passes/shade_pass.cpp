// "shade": every pixel once from its triangle id, then the edge fragments,
// in batches of runs of points on one triangle.
#include <algorithm>
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

}  // namespace

void add_shade_pass(FrameGraph& graph, const FrameContext& ctx, const SurfaceLookup& surfaces_of,
                    const EngineResources& engine, EngineTargets& targets, uint64_t& pixels_shaded) {
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
  }, [ctx, &surfaces_of, &pixels_shaded](const FrameGraph::Resources& r, const Data& d) {
    const Visibility& vis = r.get(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    const SurfaceShader shader = frame_shader(ctx, r.get(d.light), r.get(d.shadow));
    const float emissive = emissive_luminance(ctx.description);
    const int w = buffers.width, h = buffers.height;
    const std::vector<uint32_t>& ids = ctx.profile.msaa_samples == 1 ? vis.raster.visibility().triangle : vis.pixel_ids;
    // Without a sky plugin the background is the ambient radiance: a flat sky.
    const glm::vec3 background = ctx.description.ambient;
    std::vector<uint64_t> shaded_rows(size_t(h), 0);
    jobs.parallel_for("shade", size_t(h), 4, [&](size_t y0, size_t y1) {
      // Pixels of a row are shaded in batches of runs of pixels on one triangle.
      ShadeQueue q;
      SurfaceBatch& surfaces = q.surfaces;
      const Material** materials = q.materials;
      size_t* where = q.where;
      auto flush = [&] {
        q.flush(ctx.scene, emissive, shader,
                [&](size_t pixel, const glm::vec3& c) { buffers.color[pixel] = c; });
      };
      // Neighbouring pixels mostly see the same triangle: set it up once.
      uint32_t current_id = kNoTriangle;
      std::optional<TriangleSurface> triangle;
      const TriangleInterp* interp = nullptr;
      const Material* material = nullptr;
      for (size_t y = y0; y < y1; ++y) {
        uint64_t n = 0;
        for (int x = 0; x < w;) {
          const size_t i = y * size_t(w) + size_t(x);
          if (ids[i] == kNoTriangle || is_edge_pixel(ids[i])) {  // edge pixels: their fragments, below
            buffers.color[i] = background;
            ++x;
            continue;
          }
          if (ids[i] != current_id) {
            triangle.emplace(surfaces_of.triangle(vis.raster, ids[i], material));
            interp = &vis.raster.interp(ids[i]);
            current_id = ids[i];
          }
          // The run of pixels on this triangle, as far as the batch has room.
          const int room = SurfaceBatch::kCapacity - surfaces.count;
          int span = 1;
          while (span < room && x + span < w && ids[i + size_t(span)] == current_id) ++span;
          for (int k = 0; k < span; ++k) {
            where[surfaces.count + k] = i + size_t(k);
            materials[surfaces.count + k] = material;
          }
          triangle->add_span(surfaces, *interp, x, span, int(y));
          if (surfaces.full()) flush();
          x += span;
          n += uint64_t(span);
        }
        shaded_rows[y] = n;
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

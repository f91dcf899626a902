// "geometry": the draws in view (frustum culling; blended draws sorted back to
// front), rasterized into the visibility buffer and depth.
#include "engine/raster/blend_order.h"
#include "engine/render/passes/draw_culling.h"
#include "engine/render/passes/draw_materials.h"
#include "engine/render/passes/engine_passes.h"

namespace cr {

namespace {

// Draws outside the view frustum cost nothing past this test.
void cull_and_sort(const Scene& scene, const Camera& cam, Visibility& vis) {
  vis.opaque.clear();
  vis.blended.clear();
  std::vector<glm::dvec3> blend_centres;
  const glm::mat4 view_proj = cam.view_proj();
  for (uint32_t i = 0; i < scene.draws.size(); ++i) {
    const Draw& d = scene.draws[i];
    if (!aabb_in_view(cam, d.world_bounds_min, d.world_bounds_max)) continue;
    const Material& m = material_of(scene, scene.primitive(d));
    RasterDraw rd{&scene.primitive(d), model_to_clip(view_proj, cam.position, d.world), m.double_sided,
                  d.mirrored, m.alpha_mode == AlphaMode::Mask, i};
    if (m.alpha_mode != AlphaMode::Blend) {
      vis.opaque.push_back(rd);
      continue;
    }
    vis.blended.push_back(rd);
    blend_centres.push_back(0.5 * (glm::dvec3(d.world_bounds_min) + glm::dvec3(d.world_bounds_max)));
  }
  if (!vis.blended.empty()) {
    std::vector<RasterDraw> sorted;
    for (uint32_t i : back_to_front_order(blend_centres, cam.position, cam.forward)) sorted.push_back(vis.blended[i]);
    vis.blended.swap(sorted);
  }
}

}  // namespace

void add_geometry_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine,
                       EngineTargets& targets) {
  struct Data {
    FrameGraphId<Visibility> visibility;
    FrameGraphId<FrameBuffers> depth;
  };
  graph.add_pass<Data>("geometry", [&](FrameGraph::Builder& b, Data& d) {
    d.visibility = targets.visibility = b.write(targets.visibility);
    d.depth = engine.depth = b.write(engine.depth);
  }, [ctx](const FrameGraph::Resources& r, const Data& d) {
    Visibility& vis = r.get_mutable(d.visibility);
    FrameBuffers& buffers = r.get_mutable(d.depth);
    JobSystem& jobs = r.jobs();
    const Camera& cam = ctx.view.camera;
    const int samples = ctx.profile.msaa_samples;
    cull_and_sort(ctx.scene, cam, vis);
    vis.stats = vis.raster.render_visibility(jobs, buffers.width, buffers.height, ctx.profile.tile_size, vis.opaque,
                                             alpha_coverage(ctx.scene, vis.raster), samples, ctx.profile.depth_format);
    if (samples == 1) {
      buffers.depth = vis.raster.visibility().depth;
      buffers.fragments.clear();
    } else {
      classify_samples(vis.raster, cam, jobs, vis.pixel_ids, buffers.depth, buffers.fragments, vis.fragment_rows);
    }
  });
}

}  // namespace cr

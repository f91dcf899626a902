// "transparent": the blended draws in view, back to front, over the shaded
// colour; with multisampling at the pixel's samples, and at an edge pixel
// onto each fragment behind the surface.
#include "engine/render/passes/engine_passes.h"
#include "engine/render/passes/surface_lookup.h"

namespace cr {

void add_transparent_pass(FrameGraph& graph, const FrameContext& ctx, const SurfaceLookup& surfaces_of,
                          const EngineResources& engine, EngineTargets& targets) {
  struct Data {
    FrameGraphId<Visibility> visibility;
    FrameGraphId<ShadowMap> shadow;
    FrameGraphId<LightEnvironment> light;
    FrameGraphId<FrameBuffers> color;
  };
  graph.add_pass<Data>("transparent", [&](FrameGraph::Builder& b, Data& d) {
    // Blended draws rasterize through the view's rasterizer (its bins), and
    // test against the depth the geometry pass wrote.
    b.read(targets.visibility);
    d.visibility = targets.visibility = b.write(targets.visibility);
    d.shadow = b.read(engine.shadow);
    d.light = b.read(engine.light);
    b.read(engine.depth);
    b.read(targets.color);
    d.color = targets.color = b.write(targets.color);
  }, [ctx, &surfaces_of](const FrameGraph::Resources& r, const Data& d) {
    Visibility& vis = r.get_mutable(d.visibility);
    if (vis.blended.empty()) return;
    FrameBuffers& buffers = r.get_mutable(d.color);
    const SurfaceShader shader = frame_shader(ctx, r.get(d.light), r.get(d.shadow));
    const glm::dvec3 eye = ctx.view.camera.position;
    const int w = buffers.width;
    std::vector<EdgeFragment>& fragments = buffers.fragments;
    // Over a share `coverage` of the pixel the surface blends with its alpha:
    // on the pixel's box that is alpha * coverage over all of it.
    auto blend = [](glm::vec3& dst, const glm::vec3& c, float a) { dst = dst * (1.0f - a) + c * a; };
    const FragmentFn fragment = [&](int x, int y, uint32_t id, const Barycentrics& bary, float coverage) {
      const Material* m = nullptr;
      const SurfaceSample surface = surfaces_of.triangle(vis.raster, id, m).at(bary);
      const glm::vec4 shaded = shader.shade(*m, surface);
      const glm::vec3 c(shaded);
      const float a = shaded.a * coverage;
      const size_t pixel = size_t(y) * size_t(w) + size_t(x);
      blend(buffers.color[pixel], c, a);
      if (fragments.empty() || !is_edge_pixel(vis.pixel_ids[pixel])) return;
      // An edge pixel: the surface, seen at its samples' centroid, covers the
      // fragments behind it (its coverage spread evenly over them).
      const float dist = float(glm::length(glm::dvec3(surface.position) - eye));
      for (size_t f = first_fragment(vis.pixel_ids[pixel]); f < fragments.size() && fragments[f].pixel == pixel; ++f)
        if (fragments[f].distance > dist) blend(fragments[f].color, c, a);
    };
    vis.raster.render_blended(r.jobs(), vis.blended, fragment,
                              ctx.profile.msaa_samples == 1 ? std::span<const float>()
                                                            : std::span<const float>(buffers.depth));
  });
}

}  // namespace cr

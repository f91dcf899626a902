// "resolve": edge pixels become the weighted sum of their fragments; then
// exposure, ACES tonemap and 8-bit sRGB into the display image.
#include "engine/render/display_transform.h"
#include "engine/render/passes/engine_passes.h"

namespace cr {

void add_resolve_pass(FrameGraph& graph, const FrameContext& ctx, std::unique_ptr<DisplayTransform>& display,
                      std::unique_ptr<Hdr16Display>& fixed_display, EngineTargets& targets) {
  struct Data {
    FrameGraphId<FrameBuffers> color, display;
  };
  graph.add_pass<Data>("resolve", [&](FrameGraph::Builder& b, Data& d) {
    b.read(targets.color);
    d.color = targets.color = b.write(targets.color);  // edge pixels' fragments resolve into their pixels
    d.display = targets.display = b.write(targets.display);
  }, [ev100 = ctx.description.exposure_ev100, fixed = ctx.profile.fixed_resolve, &display, &fixed_display](
         const FrameGraph::Resources& r, const Data& d) {
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    const int w = buffers.width, h = buffers.height;
    if (!display || display->ev100() != ev100) display = std::make_unique<DisplayTransform>(ev100);
    if (fixed && (!fixed_display || fixed_display->ev100() != ev100))
      fixed_display = std::make_unique<Hdr16Display>(*display);
    resolve_fragments(buffers.fragments, buffers.color, jobs);
    jobs.parallel_for("resolve", size_t(h), 16, [&](size_t y0, size_t y1) {
      const glm::vec3* hdr = &buffers.color[y0 * size_t(w)];
      uint8_t* out = &buffers.display[y0 * size_t(w) * 3];
      if (fixed)
        fixed_display->resolve(hdr, (y1 - y0) * size_t(w), out);
      else
        display->resolve(hdr, (y1 - y0) * size_t(w), out);
    });
  });
}

}  // namespace cr

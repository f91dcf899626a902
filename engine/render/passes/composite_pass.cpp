// "composite": the plugins' per-pixel composites in their order, over
// full-width strips, then over the edge fragments.
#include <algorithm>

#include "engine/render/composite_strips.h"
#include "engine/render/passes/engine_passes.h"

namespace cr {

void add_composite_pass(FrameGraph& graph, const std::vector<Plugin*>& compositors, const EngineResources& engine,
                        EngineTargets& targets) {
  struct Data {
    FrameGraphId<FrameBuffers> color;
  };
  graph.add_pass<Data>("composite", [&](FrameGraph::Builder& b, Data& d) {
    b.read(engine.depth);
    b.read(engine.distance);
    b.read(targets.color);
    for (Plugin* p : compositors)
      for (const FrameGraphHandle& h : p->composite_reads()) b.read(h);
    d.color = targets.color = b.write(targets.color);
  }, [compositors](const FrameGraph::Resources& r, const Data& d) {
    FrameBuffers& buffers = r.get_mutable(d.color);
    JobSystem& jobs = r.jobs();
    for_each_composite_strip(jobs, "composite", buffers.width, buffers.height, [&](int x0, int y0, int x1, int y1) {
      for (Plugin* p : compositors) p->composite(buffers, x0, y0, x1, y1);
    });
    std::vector<EdgeFragment>& fragments = buffers.fragments;
    const size_t grain = 512, n = (fragments.size() + grain - 1) / grain;
    jobs.parallel_for("composite fragments", n, 1, [&](size_t c0, size_t c1) {
      const size_t f0 = c0 * grain, f1 = std::min(c1 * grain, fragments.size());
      for (Plugin* p : compositors) p->composite_fragments(buffers, std::span<EdgeFragment>(&fragments[f0], f1 - f0));
    });
  });
}

}  // namespace cr

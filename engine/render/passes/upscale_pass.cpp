// "upscale" (render_scale below 1): the internal frame's edge fragments
// resolve into their pixels, so its HDR colour is complete; then colour,
// depth and (when kept) distance are upscaled into the output buffers.
#include "engine/render/edge_fragments.h"
#include "engine/render/passes/engine_passes.h"
#include "engine/render/upscale.h"

namespace cr {

void add_upscale_pass(FrameGraph& graph, const Upscaler& upscaler, const EngineResources& engine,
                      EngineTargets& targets, FrameGraphId<FrameBuffers> output, bool distances, float exposure) {
  struct Data {
    FrameGraphId<FrameBuffers> source, distance, output;
  };
  graph.add_pass<Data>("upscale", [&](FrameGraph::Builder& b, Data& d) {
    b.read(targets.color);
    b.read(engine.depth);
    if (distances) d.distance = b.read(engine.distance);
    d.source = targets.color = b.write(targets.color);  // edge pixels' fragments resolve into their pixels
    d.output = targets.color = b.write(output);
  }, [&upscaler, exposure](const FrameGraph::Resources& r, const Data& d) {
    FrameBuffers& source = r.get_mutable(d.source);
    FrameBuffers& out = r.get_mutable(d.output);
    JobSystem& jobs = r.jobs();
    resolve_fragments(source.fragments, source.color, jobs);
    upscaler.color(source.color, out.color, jobs, exposure);
    upscaler.nearest(source.depth, out.depth, jobs);
    if (d.distance.valid()) upscaler.nearest(r.get(d.distance).distance, out.distance, jobs);
  });
}

}  // namespace cr

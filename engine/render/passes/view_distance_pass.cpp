// "view distance": each pixel's distance along its view ray, from depth,
// for the plugins that read it (aerial perspective, fog) and for outputs
// that keep it (an EXR frame's depth channel).
#include "engine/render/passes/engine_passes.h"
#include "engine/render/view_distance.h"

namespace cr {

void add_view_distance_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) {
  struct Data {
    FrameGraphId<FrameBuffers> depth, distance;
  };
  graph.add_pass<Data>("view distance", [&](FrameGraph::Builder& b, Data& d) {
    d.depth = b.read(engine.depth);
    d.distance = engine.distance = b.write(engine.distance);
  }, [cam = ctx.view.camera](const FrameGraph::Resources& r, const Data& d) {
    FrameBuffers& buffers = r.get_mutable(d.distance);
    view_distances(cam, buffers.width, buffers.height, r.get(d.depth).depth, buffers.distance, r.jobs());
  });
}

}  // namespace cr

// "light": the sun and ambient terms of the scene file. The light-environment
// provider (the sky) rewrites them after this pass.
#include "engine/render/passes/engine_passes.h"
#include "engine/shading/sh_lighting.h"

namespace cr {

void add_light_pass(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) {
  struct Data {
    FrameGraphId<LightEnvironment> light;
  };
  graph.add_pass<Data>(
      "light", [&](FrameGraph::Builder& b, Data& d) { d.light = engine.light = b.write(engine.light); },
      [sun = ctx.view.sun_direction, illuminance = sun_is_up(ctx.view) ? ctx.view.sun_illuminance : glm::vec3(0.0f),
       ambient = ctx.description.ambient](const FrameGraph::Resources& r, const Data& d) {
        LightEnvironment& light = r.get_mutable(d.light);
        light = LightEnvironment{};
        light.sun_direction = sun;
        light.sun_illuminance = illuminance;
        light.ambient_sh = sh_constant_radiance(ambient);
      });
}

}  // namespace cr

#include "atmosphere/atmosphere_plugin.h"

#include <cmath>
#include <iostream>

#include "atmosphere/atmosphere_memory.h"
#include "engine/render/plugin_registry.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere/sky_lighting.h"
#include "engine/render/frame_graph.h"
#include "engine/render/frame_view.h"

namespace cr {

bool AtmospherePlugin::configure(const Scene& scene, const SceneDescription& description, const Profile& profile) {
  auto it = description.plugins.find("atmosphere");
  if (it == description.plugins.end() || it->is_null()) return false;
  scene_ = parse_atmosphere_scene(*it, description.path);
  auto pit = profile.plugins.find("atmosphere");
  settings_ = parse_atmosphere_settings(pit == profile.plugins.end() ? nlohmann::json() : *pit, profile.path);
  if (orthographic_view(scene, description)) {
    // The sky view, the aerial perspective froxels and the composite are
    // built on a perspective view's rays.
    std::cerr << description.path << ": warning: the atmosphere needs a perspective view; the orthographic "
              << "camera's frames are lit by the scene's ambient and sun alone\n";
    return false;
  }
  scheduler_ = std::make_unique<LutScheduler>(settings_);
  scheduler_->set_model(scene_.model);
  environment_ = std::make_unique<SkyEnvironment>(settings_);
  return true;
}

void AtmospherePlugin::estimate_memory(const SceneDescription& description, const Profile& profile,
                                       MemoryBudget& memory) const {
  auto it = description.plugins.find("atmosphere");
  if (it == description.plugins.end() || it->is_null()) return;
  auto pit = profile.plugins.find("atmosphere");
  estimate_atmosphere_memory(parse_atmosphere_settings(pit == profile.plugins.end() ? nlohmann::json() : *pit, profile.path),
                             profile.path, memory);
}

void AtmospherePlugin::add_passes(FrameGraph& graph, FrameContext& ctx) {
  const glm::dvec3 offset = planet_offset(scene_);
  plan_ = scheduler_->plan(frame_inputs(scene_.model, offset, ctx.view.frame, ctx.view.camera, ctx.view.sun_direction));
  LutScheduler* sched = scheduler_.get();
  JobSystem* jobs = &ctx.jobs;
  const AtmospherePlan* plan = &plan_;
  static const char* const kResources[kLutKinds] = {"atmosphere.transmittance", "atmosphere.multiscattering",
                                                    "atmosphere.skyview", "atmosphere.aerial_perspective"};
  for (int k = 0; k < kLutKinds; ++k) {
    if (!plan_.work[size_t(k)].active) continue;
    const LutKind kind = LutKind(k);
    graph.add_pass(
        kResources[k],
        [k](FrameGraph::Builder& b) {
          if (k >= 1) b.read(kResources[0]);
          if (k >= 2) b.read(kResources[1]);
          b.write(kResources[k]);
        },
        [sched, jobs, plan, kind] { sched->run(kind, *plan, *jobs); });
  }
  const Camera camera = ctx.view.camera;
  const glm::vec3 illuminance = ctx.view.sun_illuminance;
  SkyFrame* sky = &sky_;
  graph.add_pass(
      "atmosphere.sky",
      [](FrameGraph::Builder& b) {
        for (const char* r : kResources) b.read(r);
        b.write("atmosphere.sky");
      },
      [sched, plan, sky, camera, offset, illuminance] {
        *sky = make_sky_frame(*sched, *plan, camera, offset, illuminance);
      });
  SkyEnvironment* env = environment_.get();
  const uint64_t upstream = sched->version(LutKind::MultiScattering) +
                            (plan_.work[size_t(LutKind::MultiScattering)].publishes ? 1 : 0);
  environment_work_ = env->plan(plan_, upstream);
  if (environment_work_.active) {
    const EnvironmentWork* work = &environment_work_;
    graph.add_pass(
        "atmosphere.environment",
        [](FrameGraph::Builder& b) {
          b.read("atmosphere.sky");
          b.write("atmosphere.environment");
        },
        [env, work, plan, upstream, sky, jobs] { env->run(*work, *plan, upstream, *sky, *jobs); });
  }
  LightEnvironment* light = &ctx.light;
  graph.add_pass(
      "atmosphere.lighting",
      [](FrameGraph::Builder& b) {
        b.read("atmosphere.sky");
        b.read("atmosphere.environment");
        b.write("light_environment");
      },
      [sky, light, env] { fill_light_environment(*sky, *light, env->front()); });
}

void AtmospherePlugin::composite(const FrameContext& ctx, int x0, int y0, int x1, int y1) {
  composite_sky(sky_, ctx.buffers, x0, y0, x1, y1);
}

void AtmospherePlugin::composite_fragments(const FrameContext& ctx, std::span<EdgeFragment> fragments) {
  composite_sky_fragments(sky_, ctx.buffers.width, ctx.buffers.height, fragments);
}

void AtmospherePlugin::report_frame(nlohmann::json& frame) {
  if (!scheduler_) return;
  nlohmann::json r = scheduler_->report(plan_);
  for (auto it = r.begin(); it != r.end(); ++it) frame[it.key()] = it.value();
  frame["environment"] = environment_->report(environment_work_, plan_.frame);
}

void register_atmosphere_plugin(PluginRegistry& registry) {
  registry.add("atmosphere", [] { return std::make_unique<AtmospherePlugin>(); });
}

}  // namespace cr

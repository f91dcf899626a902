#include "atmosphere/atmosphere_plugin.h"

#include <algorithm>
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

void AtmospherePlugin::add_passes(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) {
  using Builder = FrameGraph::Builder;
  using Resources = FrameGraph::Resources;
  const glm::dvec3 offset = planet_offset(scene_);
  plan_ = scheduler_->plan(frame_inputs(scene_.model, offset, ctx.view.frame, ctx.view.camera, ctx.view.sun_direction));
  const AtmospherePlan* plan = &plan_;
  // The four LUTs persist across frames (imported); a LUT's pass runs only in
  // frames where its schedule has work.
  static const char* const kResources[kLutKinds] = {"atmosphere.transmittance", "atmosphere.multiscattering",
                                                    "atmosphere.skyview", "atmosphere.aerial_perspective"};
  FrameGraphId<LutScheduler> luts[kLutKinds];
  for (int k = 0; k < kLutKinds; ++k) luts[k] = graph.import(kResources[k], *scheduler_);
  struct LutData {
    FrameGraphId<LutScheduler> lut;
  };
  for (int k = 0; k < kLutKinds; ++k) {
    if (!plan_.work[size_t(k)].active) continue;
    const LutKind kind = LutKind(k);
    graph.add_pass<LutData>(
        kResources[k],
        [&luts, k](Builder& b, LutData& d) {
          if (k >= 1) b.read(luts[0]);
          if (k >= 2) b.read(luts[1]);
          d.lut = luts[k] = b.write(luts[k]);
        },
        [plan, kind](const Resources& r, const LutData& d) { r.get_mutable(d.lut).run(kind, *plan, r.jobs()); });
  }
  struct SkyData {
    FrameGraphId<LutScheduler> luts;
    FrameGraphId<SkyFrame> sky;
  };
  sky_handle_ = graph.create("atmosphere.sky", sky_);
  graph.add_pass<SkyData>(
      "atmosphere.sky",
      [&](Builder& b, SkyData& d) {
        for (const FrameGraphId<LutScheduler>& lut : luts) d.luts = b.read(lut);  // one object holds all four
        d.sky = sky_handle_ = b.write(sky_handle_);
      },
      [plan, camera = ctx.view.camera, offset, illuminance = ctx.view.sun_illuminance](const Resources& r,
                                                                                         const SkyData& d) {
        r.get_mutable(d.sky) = make_sky_frame(r.get(d.luts), *plan, camera, offset, illuminance);
      });
  FrameGraphId<SkyEnvironment> environment = graph.import("atmosphere.environment", *environment_);
  const uint64_t upstream = scheduler_->version(LutKind::MultiScattering) +
                            (plan_.work[size_t(LutKind::MultiScattering)].publishes ? 1 : 0);
  environment_work_ = environment_->plan(plan_, upstream);
  struct EnvironmentData {
    FrameGraphId<SkyFrame> sky;
    FrameGraphId<SkyEnvironment> environment;
  };
  if (environment_work_.active) {
    const EnvironmentWork* work = &environment_work_;
    graph.add_pass<EnvironmentData>(
        "atmosphere.environment",
        [&](Builder& b, EnvironmentData& d) {
          d.sky = b.read(sky_handle_);
          d.environment = environment = b.write(environment);
        },
        [work, plan, upstream](const Resources& r, const EnvironmentData& d) {
          r.get_mutable(d.environment).run(*work, *plan, upstream, r.get(d.sky), r.jobs());
        });
  }
  struct LightingData {
    FrameGraphId<SkyFrame> sky;
    FrameGraphId<SkyEnvironment> environment;
    FrameGraphId<LightEnvironment> light;
  };
  graph.add_pass<LightingData>(
      "atmosphere.lighting",
      [&](Builder& b, LightingData& d) {
        d.sky = b.read(sky_handle_);
        d.environment = b.read(environment);
        d.light = engine.light = b.write(engine.light);
      },
      [](const Resources& r, const LightingData& d) {
        fill_light_environment(r.get(d.sky), r.get_mutable(d.light), r.get(d.environment).front());
      });
}

void AtmospherePlugin::composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) {
  composite_sky(sky_, buffers, x0, y0, x1, y1);
}

void AtmospherePlugin::composite_fragments(const FrameBuffers& buffers, std::span<EdgeFragment> fragments) {
  composite_sky_fragments(sky_, buffers.width, buffers.height, fragments);
}

int AtmospherePlugin::warmup_frames(double tolerance) const {
  (void)tolerance;  // LUTs are rebuilt whole, not blended: no decay to wait for
  if (settings_.full_schedule) return 0;  // rebuilt every frame: nothing carried
  // Within one period plus the slices of a rebuild every LUT (and the
  // environment) has been rebuilt from this stretch of the path, as in a
  // render from the start; what remains is which frames the rebuilds started
  // on (the invalidation thresholds bound what that changes).
  int frames = settings_.environment_schedule.period + settings_.environment_schedule.slices;
  for (const LutSchedule& s : settings_.schedule) frames = std::max(frames, s.period + s.slices);
  return frames;
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

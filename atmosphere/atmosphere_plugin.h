#pragma once
// The atmosphere as an engine plugin: Hillaire 2020 sky, sun and aerial
// perspective with amortised LUT updates (see lut_scheduler.h).
//
// Passes (each added only in frames where its LUT has work):
//   atmosphere.transmittance       writes atmosphere.transmittance
//   atmosphere.multiscattering     reads transmittance, writes atmosphere.multiscattering
//   atmosphere.skyview             reads both, writes atmosphere.skyview
//   atmosphere.aerial_perspective  reads both, writes atmosphere.aerial_perspective
//   atmosphere.environment         reads atmosphere.sky, writes atmosphere.environment
//                                  (a slice of the prefiltered specular environment, sky_environment.h)
// and every frame:
//   atmosphere.sky                 reads the LUTs, writes atmosphere.sky (the composite's input)
//   atmosphere.lighting            reads atmosphere.sky and atmosphere.environment, writes light_environment
// The plugin provides the light environment: the renderer declares these
// passes before any other plugin's, so the fog and shading read its light.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/lut_scheduler.h"
#include "atmosphere/planet_frame.h"
#include "atmosphere/sky_environment.h"
#include "atmosphere/sky_frame.h"
#include "engine/render/plugin.h"

namespace cr {

class PluginRegistry;

class AtmospherePlugin : public Plugin {
 public:
  std::string name() const override { return "atmosphere"; }
  bool configure(const Scene& scene, const SceneDescription& description, const Profile& profile) override;
  void estimate_memory(const SceneDescription& description, const Profile& profile,
                       MemoryBudget& memory) const override;
  bool provides_light_environment() const override { return true; }
  void add_passes(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) override;
  std::vector<FrameGraphHandle> composite_reads() const override { return {sky_handle_}; }
  int composite_order() const override { return 100; }
  bool has_composite() const override { return true; }
  bool composites_background() const override { return true; }
  void composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) override;
  void composite_fragments(const FrameBuffers& buffers, std::span<EdgeFragment> fragments) override;
  void report_frame(nlohmann::json& frame) override;
  int warmup_frames(double tolerance) const override;
  ModulePlan plan(const PlanContext& ctx) const override;  // *_plan.cpp

  const LutScheduler* scheduler() const { return scheduler_.get(); }
  const SkyFrame& sky_frame() const { return sky_; }
  const SkyEnvironment* environment() const { return environment_.get(); }

 private:
  AtmosphereSceneConfig scene_;
  AtmosphereSettings settings_;
  std::unique_ptr<LutScheduler> scheduler_;
  AtmospherePlan plan_;
  SkyFrame sky_;
  FrameGraphId<SkyFrame> sky_handle_;  // sky_ in this frame's graph, as the sky pass wrote it
  std::unique_ptr<SkyEnvironment> environment_;
  EnvironmentWork environment_work_;
};

// Adds the "atmosphere" plugin factory.
void register_atmosphere_plugin(PluginRegistry& registry);

}  // namespace cr

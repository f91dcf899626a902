#pragma once
// The froxel fog as an engine plugin ("fog"): validates the scene's and the
// profile's "fog" sections, declares the passes fog.density (reads depth, for
// depth-aware froxel culling) -> fog.lighting
// (reads shadow_map and previous_shadow_map) -> fog.reproject -> fog.filter -> fog.integrate (reads
// light_environment, writes fog.volume), and composites per pixel after the
// atmosphere (order 200). A scene without a "fog" section adds no pass.
#include <memory>
#include <string>
#include <vector>

#include "engine/render/plugin.h"
#include "fog/froxel_fog.h"

namespace cr {

class PluginRegistry;

class FogPlugin : public Plugin {
 public:
  std::string name() const override { return "fog"; }
  bool configure(const Scene& scene, const SceneDescription& description, const Profile& profile) override;
  void estimate_memory(const SceneDescription& description, const Profile& profile,
                       MemoryBudget& memory) const override;
  void add_passes(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) override;
  std::vector<FrameGraphHandle> composite_reads() const override { return {volume_}; }
  int composite_order() const override { return 200; }
  bool has_composite() const override { return true; }
  void composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) override;
  void composite_fragments(const FrameBuffers& buffers, std::span<EdgeFragment> fragments) override;
  void report_frame(nlohmann::json& frame) override;
  int warmup_frames(double tolerance) const override;
  ModulePlan plan(const PlanContext& ctx) const override;  // *_plan.cpp

  // The fog state (for commands and tests); null before configure().
  FroxelFog* fog() { return fog_.get(); }

 private:
  std::unique_ptr<FroxelFog> fog_;
  FrameGraphId<FroxelFog> volume_;  // this frame's integrated volume, the composite's input
};

// Adds the "fog" plugin factory to the registry.
void register_fog_plugin(PluginRegistry& registry);

}  // namespace cr

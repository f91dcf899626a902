#include "fog/fog_plugin.h"

#include <iostream>

#include "engine/render/frame_graph.h"
#include "engine/render/frame_view.h"
#include "engine/render/plugin_registry.h"

namespace cr {

bool FogPlugin::configure(const Scene& scene, const SceneDescription& description, const Profile& profile) {
  // The profile section is validated even when the scene has no fog, so a
  // bad profile is reported whatever scene it is used with.
  FogProfileSettings p;
  if (profile.plugins.contains("fog")) p = parse_fog_profile(profile.plugins.at("fog"), profile.path);
  fog_.reset();
  if (!description.plugins.contains("fog")) return false;
  const FogSceneSettings s = parse_fog_scene(description.plugins.at("fog"), description.path);
  if (orthographic_view(scene, description)) {
    std::cerr << description.path << ": warning: froxel fog needs a perspective view; the orthographic camera's "
              << "frames have no fog\n";
    return false;
  }
  fog_ = std::make_unique<FroxelFog>(p, s);
  return true;
}

void FogPlugin::estimate_memory(const SceneDescription& description, const Profile& profile,
                                MemoryBudget& memory) const {
  if (!description.plugins.contains("fog")) return;
  FogProfileSettings p;
  if (profile.plugins.contains("fog")) p = parse_fog_profile(profile.plugins.at("fog"), profile.path);
  const size_t columns = saturating_product({size_t((profile.width + p.froxel_size_px - 1) / p.froxel_size_px),
                                             size_t((profile.height + p.froxel_size_px - 1) / p.froxel_size_px)});
  // Per froxel: density, the integrated froxel and its sun knot, and ten
  // float planes (sun visibility now, two histories, filter scratch and
  // result, the still mean, light change, integrated visibility, masks).
  const size_t per_froxel = sizeof(FogDensity) + sizeof(IntegratedFroxel) + sizeof(glm::vec3) + 10 * sizeof(float);
  memory.charge("froxel grid of " + std::to_string(columns) + " columns x " + std::to_string(p.slices) + " slices",
                profile.path, "fog.froxel_size_px", saturating_product({columns, size_t(p.slices), per_froxel}));
}

void FogPlugin::add_passes(FrameGraph& graph, FrameContext& ctx) {
  FroxelFog* fog = fog_.get();
  FrameContext* c = &ctx;
  const FogProfileSettings& p = fog->profile();
  graph.add_pass(
      "fog.density", [](FrameGraph::Builder& b) { b.read("depth").write("fog.density"); },
      [fog, c] {
        fog->begin_frame(c->view, c->jobs, &c->buffers.distance);
        fog->density();
      });
  graph.add_pass(
      "fog.lighting",
      [](FrameGraph::Builder& b) {
        b.read("fog.density").read("shadow_map").write("fog.lighting");
      },
      [fog, c] { fog->lighting(c->shadow, c->jobs, &c->previous_shadow); });
  std::string sun = "fog.lighting";
  if (p.reprojection) {
    graph.add_pass(
        "fog.reproject", [](FrameGraph::Builder& b) { b.read("fog.lighting").write("fog.history"); },
        [fog, c] { fog->reproject(c->jobs); });
    sun = "fog.history";
  }
  if (p.filter) {
    graph.add_pass(
        "fog.filter", [sun](FrameGraph::Builder& b) { b.read(sun).write("fog.filtered"); },
        [fog, c] { fog->filter(c->jobs); });
    sun = "fog.filtered";
  }
  graph.add_pass(
      "fog.integrate",
      [sun](FrameGraph::Builder& b) { b.read("fog.density").read(sun).read("light_environment").write("fog.volume"); },
      [fog, c] { fog->integrate(c->light, c->jobs); });
}

void FogPlugin::composite(const FrameContext& ctx, int x0, int y0, int x1, int y1) {
  fog_->composite(ctx.buffers, x0, y0, x1, y1);
}

void FogPlugin::composite_fragments(const FrameContext&, std::span<EdgeFragment> fragments) {
  fog_->composite_fragments(fragments);
}

void FogPlugin::report_frame(nlohmann::json& frame) {
  if (!fog_) return;
  const FroxelGrid& g = fog_->grid();
  const FroxelFogStats& s = fog_->stats();
  frame["froxels"] = {g.nx(), g.ny(), g.nz()};
  frame["fog_range_m"] = {g.near_distance(), g.far_distance()};
  frame["visible_volumes"] = s.voxelize.visible_volumes;
  frame["volume_froxels"] = s.voxelize.volume_froxels;
  frame["lit_froxels"] = s.lit_froxels;
  frame["active_froxels"] = s.active_froxels;
  frame["history_used"] = s.history_used;
  frame["history_read_froxels"] = s.reproject.reads;
  frame["history_rejected_froxels"] = s.reproject.rejected;
  frame["light_changed"] = s.light_changed;
  frame["still_frames"] = s.still_frames;
  frame["filtered"] = s.filtered;
  frame["density_kept"] = s.density_kept;
  frame["jitter_complete"] = s.jitter_complete;
  frame["lighting_frozen"] = s.lighting_frozen;
  frame["volume_kept"] = s.volume_kept;
  frame["integrated_froxels"] = s.integrated_froxels;
  frame["unsettled_froxels"] = s.unsettled_froxels;
}

void register_fog_plugin(PluginRegistry& registry) {
  registry.add("fog", [] { return std::make_unique<FogPlugin>(); });
}

}  // namespace cr

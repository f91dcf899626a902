#include "fog/fog_plugin.h"

#include "fog/jitter_sequence.h"

#include <cmath>
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
  if (!has_fog_media(s)) return false;  // nothing to scatter in: no passes, no cost
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
  if (!description.plugins.contains("fog") ||
      !has_fog_media(parse_fog_scene(description.plugins.at("fog"), description.path)))
    return;
  FogProfileSettings p;
  if (profile.plugins.contains("fog")) p = parse_fog_profile(profile.plugins.at("fog"), profile.path);
  // The grid covers the internal size the scene renders at (render_scale).
  const size_t columns =
      saturating_product({size_t((profile.render_width() + p.froxel_size_px - 1) / p.froxel_size_px),
                           size_t((profile.render_height() + p.froxel_size_px - 1) / p.froxel_size_px)});
  // Per froxel: density, the integrated froxel and its sun knot, and ten
  // float planes (sun visibility now, two histories, filter scratch and
  // result, the still mean, light change, integrated visibility, masks);
  // with "precision": "fixed" the eight planes of the sun term are 16-bit
  // codes, and the still run's sum and the masks 32-bit.
  const size_t per_froxel = sizeof(FogDensity) + sizeof(glm::vec3) +
                            (p.precision == FogPrecision::Fixed
                                 ? sizeof(FixedIntegratedFroxel) + 8 * sizeof(uint16_t) + 2 * sizeof(uint32_t)
                                 : sizeof(IntegratedFroxel) + 10 * sizeof(float));
  memory.charge("froxel grid of " + std::to_string(columns) + " columns x " + std::to_string(p.slices) + " slices",
                profile.path, "fog.froxel_size_px", saturating_product({columns, size_t(p.slices), per_froxel}));
}

void FogPlugin::add_passes(FrameGraph& graph, const FrameContext& ctx, EngineResources& engine) {
  using Builder = FrameGraph::Builder;
  using Resources = FrameGraph::Resources;
  // Each stage's output lives in the FroxelFog; the history persists across frames.
  FroxelFog& fog = *fog_;
  const FogProfileSettings& p = fog.profile();
  FrameGraphId<FroxelFog> density = graph.create("fog.density", fog);
  FrameGraphId<FroxelFog> sun = graph.create("fog.lighting", fog);  // the sun visibility integration reads
  struct DensityData {
    FrameGraphId<FrameBuffers> distance;
    FrameGraphId<FroxelFog> density;
  };
  graph.add_pass<DensityData>(
      "fog.density",
      [&](Builder& b, DensityData& d) {
        d.distance = b.read(engine.distance);
        d.density = density = b.write(density);
      },
      [view = ctx.view](const Resources& r, const DensityData& d) {
        FroxelFog& f = r.get_mutable(d.density);
        f.begin_frame(view, r.jobs(), &r.get(d.distance).distance);
        f.density();
      });
  struct LightingData {
    FrameGraphId<ShadowMap> shadow, previous_shadow;
    FrameGraphId<FroxelFog> lighting;
  };
  graph.add_pass<LightingData>(
      "fog.lighting",
      [&](Builder& b, LightingData& d) {
        b.read(density);
        d.shadow = b.read(engine.shadow);
        d.previous_shadow = b.read(engine.previous_shadow);
        d.lighting = sun = b.write(sun);
      },
      [](const Resources& r, const LightingData& d) {
        r.get_mutable(d.lighting).lighting(r.get(d.shadow), r.jobs(), &r.get(d.previous_shadow));
      });
  struct StageData {
    FrameGraphId<FroxelFog> out;
  };
  if (p.reprojection) {
    FrameGraphId<FroxelFog> history = graph.import("fog.history", fog);
    graph.add_pass<StageData>(
        "fog.reproject",
        [&](Builder& b, StageData& d) {
          b.read(sun);
          d.out = history = b.write(history);
        },
        [](const Resources& r, const StageData& d) { r.get_mutable(d.out).reproject(r.jobs()); });
    sun = history;
  }
  if (p.filter) {
    FrameGraphId<FroxelFog> filtered = graph.create("fog.filtered", fog);
    graph.add_pass<StageData>(
        "fog.filter",
        [&](Builder& b, StageData& d) {
          b.read(sun);
          d.out = filtered = b.write(filtered);
        },
        [](const Resources& r, const StageData& d) { r.get_mutable(d.out).filter(r.jobs()); });
    sun = filtered;
  }
  struct IntegrateData {
    FrameGraphId<LightEnvironment> light;
    FrameGraphId<FroxelFog> volume;
  };
  volume_ = graph.create("fog.volume", fog);
  graph.add_pass<IntegrateData>(
      "fog.integrate",
      [&](Builder& b, IntegrateData& d) {
        b.read(density);
        b.read(sun);
        d.light = b.read(engine.light);
        d.volume = volume_ = b.write(volume_);
      },
      [](const Resources& r, const IntegrateData& d) { r.get_mutable(d.volume).integrate(r.get(d.light), r.jobs()); });
}

void FogPlugin::composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) {
  fog_->composite(buffers, x0, y0, x1, y1);
}

void FogPlugin::composite_fragments(const FrameBuffers&, std::span<EdgeFragment> fragments) {
  fog_->composite_fragments(fragments);
}

int FogPlugin::warmup_frames(double tolerance) const {
  const FogProfileSettings& s = fog_->profile();
  int frames = 0;
  // The history keeps w^n of what it held n frames ago (less where it is
  // clamped or rejected), so a cold history fades below `tolerance` after
  // log(tolerance) / log(w) frames.
  if (s.reprojection && s.history_weight > 0.0f && tolerance > 0.0 && tolerance < 1.0)
    frames = int(std::ceil(std::log(tolerance) / std::log(double(s.history_weight))));
  // Then one whole jitter sequence, which a still view averages.
  if (s.jitter) frames += kJitterFrames;
  return frames;
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
  frame["history_clamped_froxels"] = s.reproject.clamped;
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

// What the fog offers the `auto` planner (engine/planning/auto_plan.h): the
// table's options where the scene has fog to scatter in, else no fog passes.
#include "engine/render/frame_view.h"
#include "fog/fog_plugin.h"

namespace cr {

ModulePlan FogPlugin::plan(const PlanContext& ctx) const {
  ModulePlan m;
  m.module = name();
  if (!ctx.description.plugins.contains("fog")) {
    m.used = false;
    m.note = "the scene has no fog section: no fog passes";
    return m;
  }
  const FogSceneSettings s = parse_fog_scene(ctx.description.plugins.at("fog"), ctx.description.path);
  if (!has_fog_media(s)) {
    m.used = false;
    m.note = "the fog section has neither height fog nor volumes: no fog passes";
    return m;
  }
  if (orthographic_view(ctx.scene, ctx.description)) {
    m.used = false;
    m.note = "an orthographic view: the froxel fog adds no passes";
    return m;
  }
  m.options = parse_plan_options(ctx.table_options, ctx.table_path, name());
  return m;
}

}  // namespace cr

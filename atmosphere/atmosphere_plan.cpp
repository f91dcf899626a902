// What the atmosphere offers the `auto` planner (engine/planning/auto_plan.h):
// the table's options, with what the scene decides on top: no sky where the
// scene has none, an aerial-perspective range that ends past the farthest
// geometry, more sky-view steps where the sun is near or below the horizon.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "atmosphere/atmosphere_plugin.h"
#include "engine/render/frame_view.h"

namespace cr {

namespace {

// Sky-view steps where the sun grazes the horizon: the in-scatter along long
// grazing paths changes over a few km that 14 steps at most skip.
constexpr int kTwilightSkyviewMaxSteps = 32;
// Margin past the farthest geometry, so the last slices are not stretched over it.
constexpr double kApRangeMargin = 1.25;

std::string km(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g km", v);
  return buf;
}

}  // namespace

ModulePlan AtmospherePlugin::plan(const PlanContext& ctx) const {
  ModulePlan m;
  m.module = name();
  const auto it = ctx.description.plugins.find("atmosphere");
  if (it == ctx.description.plugins.end() || it->is_null()) {
    m.used = false;
    m.note = "the scene has no atmosphere section: no sky passes";
    return m;
  }
  if (orthographic_view(ctx.scene, ctx.description)) {
    m.used = false;
    m.note = "an orthographic view: the atmosphere adds no passes";
    return m;
  }
  const AtmosphereSceneConfig scene = parse_atmosphere_scene(*it, ctx.description.path);
  const auto pit = ctx.base.plugins.find("atmosphere");
  const AtmosphereSettings base =
      parse_atmosphere_settings(pit == ctx.base.plugins.end() ? nlohmann::json() : *pit, ctx.base.path);
  m.options = parse_plan_options(ctx.table_options, ctx.table_path, name());
  const SceneFacts& f = ctx.facts;
  if (f.camera_static() && f.sun_static())
    m.note = "camera and sun hold still: the LUTs are built on the first frame and never again";

  if (scene.ground_altitude + f.min_camera_height_m > base.space_altitude) {
    m.note += std::string(m.note.empty() ? "" : "; ") +
              "the camera stays above the space fallback altitude: no aerial-perspective LUT";
  } else if (f.has_geometry) {
    const double range_km = f.max_geometry_distance_m * kApRangeMargin / 1000.0;
    // Three significant digits, rounded up: the range still covers the geometry.
    const double per_slice = range_km / base.ap_depth;
    const double scale = std::pow(10.0, std::floor(std::log10(per_slice)) - 2.0);
    const double rounded = std::ceil(per_slice / scale) * scale;
    if (rounded < base.ap_km_per_slice)
      m.settings.push_back({"atmosphere.aerial_perspective_lut.km_per_slice", rounded,
                            "all geometry lies within " + km(f.max_geometry_distance_m / 1000.0) +
                                ": the aerial-perspective slices end at " + km(rounded * base.ap_depth) +
                                " instead of " + km(double(base.ap_km_per_slice) * base.ap_depth)});
  }
  if (f.twilight() && base.skyview_max_steps < kTwilightSkyviewMaxSteps)
    m.settings.push_back({"atmosphere.skyview_lut.max_steps", kTwilightSkyviewMaxSteps,
                          "the sun comes within 6 degrees of the horizon: more sky-view steps along the long "
                          "grazing paths"});
  return m;
}

}  // namespace cr

#include "atmosphere/atmosphere_settings.h"

#include <algorithm>
#include <cstdio>

#include "atmosphere/config_fields.h"

namespace cr {

namespace {

// One LUT rebuild may march at most this many steps: about 2-8 s on one core
// (7-30 ns a step), so no profile can ask for a bake of minutes (desktop's
// largest, the multiscattering LUT, marches 2.6 million).
constexpr double kMaxRebuildSteps = double(1 << 28);

void require_rebuild_steps(ConfigFields& lut, const char* field, double steps, const char* what) {
  if (steps <= kMaxRebuildSteps) return;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s march %.3g steps per rebuild, more than the limit of %.3g", what, steps,
                kMaxRebuildSteps);
  lut.fail(field, buf);
}

}  // namespace

const char* lut_name(LutKind kind) {
  switch (kind) {
    case LutKind::Transmittance: return "transmittance";
    case LutKind::MultiScattering: return "multiscattering";
    case LutKind::SkyView: return "skyview";
    case LutKind::AerialPerspective: return "aerial_perspective";
  }
  return "?";
}

AtmosphereSettings parse_atmosphere_settings(const nlohmann::json& section, const std::string& file) {
  AtmosphereSettings s;
  ConfigFields f(section, file, "atmosphere");

  ConfigFields t = f.object("transmittance_lut");
  s.transmittance_width = t.integer("width", s.transmittance_width, 4, 4096);
  s.transmittance_height = t.integer("height", s.transmittance_height, 4, 4096);
  s.transmittance_steps = t.integer("steps", s.transmittance_steps, 1, 4096);
  require_rebuild_steps(t, "steps", double(s.transmittance_width) * s.transmittance_height * s.transmittance_steps,
                        "width x height x steps");
  t.finish();

  ConfigFields ms = f.object("multiscattering_lut");
  s.multiscattering_width = ms.integer("width", s.multiscattering_width, 4, 1024);
  s.multiscattering_height = ms.integer("height", s.multiscattering_height, 4, 1024);
  s.multiscattering_explicit_orders = ms.integer("explicit_orders", s.multiscattering_explicit_orders, 0, 8);
  s.multiscattering_max_explicit_orders =
      ms.integer("max_explicit_orders", std::max(s.multiscattering_max_explicit_orders, s.multiscattering_explicit_orders),
                 s.multiscattering_explicit_orders, 8);
  s.multiscattering_tail_share = float(ms.number("tail_share", s.multiscattering_tail_share, 1e-6, 1.0));
  s.multiscattering_directions = ms.integer("directions", s.multiscattering_directions, 4, 4096);
  s.multiscattering_steps = ms.integer("steps", s.multiscattering_steps, 1, 4096);
  s.multiscattering_max_fms = float(ms.number("max_fms", s.multiscattering_max_fms, 0.0, 0.999));
  {
    int n = 1;
    while (n * n < s.multiscattering_directions) ++n;
    if (n * n != s.multiscattering_directions || n % 2 != 0)
      ms.fail("directions", "must be n*n with n even (stratified, mirror-symmetric about the sun plane), e.g. 64");
  }
  // Each texel marches every direction once per explicit order and once more
  // for the series' second order.
  require_rebuild_steps(ms, "steps",
                        double(s.multiscattering_width) * s.multiscattering_height * s.multiscattering_directions *
                            s.multiscattering_steps * (1 + s.multiscattering_max_explicit_orders),
                        "width x height x directions x steps x (1 + max_explicit_orders)");
  ms.finish();

  ConfigFields sv = f.object("skyview_lut");
  s.skyview_width = sv.integer("width", s.skyview_width, 4, 4096);
  s.skyview_height = sv.integer("height", s.skyview_height, 4, 4096);
  if (s.skyview_height % 2 != 0)
    sv.fail("height", "must be even (the horizon lies between the two middle rows)");
  s.skyview_min_steps = sv.integer("min_steps", s.skyview_min_steps, 1, 1024);
  s.skyview_max_steps = sv.integer("max_steps", s.skyview_max_steps, 1, 1024);
  if (s.skyview_max_steps < s.skyview_min_steps) sv.fail("max_steps", "must be >= min_steps");
  require_rebuild_steps(sv, "max_steps", double(s.skyview_width) * s.skyview_height * s.skyview_max_steps,
                        "width x height x max_steps");
  sv.finish();

  ConfigFields ap = f.object("aerial_perspective_lut");
  s.ap_width = ap.integer("width", s.ap_width, 2, 512);
  s.ap_height = ap.integer("height", s.ap_height, 2, 512);
  s.ap_depth = ap.integer("depth", s.ap_depth, 2, 512);
  s.ap_km_per_slice = float(ap.number("km_per_slice", s.ap_km_per_slice, 0.001, 1000.0));
  s.ap_steps_per_slice = ap.integer("steps_per_slice", s.ap_steps_per_slice, 1, 64);
  require_rebuild_steps(ap, "steps_per_slice", double(s.ap_width) * s.ap_height * s.ap_depth * s.ap_steps_per_slice,
                        "width x height x depth x steps_per_slice");
  ap.finish();

  ConfigFields sched = f.object("schedule");
  s.full_schedule = sched.boolean("full", s.full_schedule);
  for (int k = 0; k < kLutKinds; ++k) {
    ConfigFields one = sched.object(lut_name(LutKind(k)));
    LutSchedule& ls = s.schedule[size_t(k)];
    ls.period = one.integer("period", ls.period, 1, 100000);
    ls.slices = one.integer("slices", ls.slices, 1, 1024);
    if (ls.slices > ls.period) one.fail("slices", "must be <= period (a rebuild must finish before the next starts)");
    one.finish();
  }
  sched.finish();

  ConfigFields env = f.object("environment");
  s.environment_size = env.integer("size", s.environment_size, 8, 256);
  if ((s.environment_size & (s.environment_size - 1)) != 0)
    env.fail("size", "must be a power of two (its box-filtered mip chain halves it), e.g. 64");
  s.environment_levels = env.integer("levels", s.environment_levels, 1, 10);
  s.environment_samples = env.integer("samples", s.environment_samples, 1, 1024);
  s.environment_schedule.period = env.integer("period", s.environment_schedule.period, 1, 100000);
  s.environment_schedule.slices = env.integer("slices", s.environment_schedule.slices, 1, 1024);
  if (s.environment_schedule.slices > s.environment_schedule.period)
    env.fail("slices", "must be <= period (a rebuild must finish before the next starts)");
  env.finish();

  ConfigFields inv = f.object("invalidation");
  s.invalidate_sun_deg = float(inv.number("sun_deg", s.invalidate_sun_deg, 0.0, 180.0));
  s.invalidate_camera_m = float(inv.number("camera_m", s.invalidate_camera_m, 0.0, 1e9));
  s.invalidate_camera_deg = float(inv.number("camera_deg", s.invalidate_camera_deg, 0.0, 180.0));
  inv.finish();

  ConfigFields prec = f.object("precision");
  const std::string luts = prec.text("luts", "float32");
  if (luts != "float32" && luts != "q15") prec.fail("luts", "must be \"float32\" or \"q15\"");
  s.lut_precision = luts == "q15" ? LutPrecision::Q15 : LutPrecision::Float32;
  const std::string composite = prec.text("composite", "float");
  if (composite != "float" && composite != "fixed") prec.fail("composite", "must be \"float\" or \"fixed\"");
  s.composite_precision = composite == "fixed" ? CompositePrecision::Fixed : CompositePrecision::Float;
  if (s.composite_precision == CompositePrecision::Fixed && s.lut_precision != LutPrecision::Q15)
    prec.fail("composite", "\"fixed\" samples the 16-bit LUTs: it needs \"luts\": \"q15\"");
  prec.finish();

  // 3: the RGB model; more: bands over 380-780 nm baked in groups of three (spectral_sampling.h).
  s.spectral_samples = f.integer("spectral_samples", s.spectral_samples, 3, 48);
  if (s.spectral_samples % 3 != 0)
    f.fail("spectral_samples", "must be a multiple of 3 (the LUTs bake wavelengths in groups of three), e.g. 3, 6, 12, 15");

  s.space_altitude = f.number("space_fallback_altitude_m", s.space_altitude, 0.0, 1e9);
  // Marched per pixel every frame in space: kept to what a frame can afford.
  s.space_steps = f.integer("space_march_steps", s.space_steps, 1, 256);
  f.finish();
  return s;
}

}  // namespace cr

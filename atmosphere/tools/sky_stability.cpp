#include "atmosphere/tools/sky_stability.h"

#include <vector>

#include "atmosphere/planet_geometry.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere/tools/reference_renderer.h"
#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_panorama.h"
#include "engine/core/luminance.h"
#include "engine/output/stability_map.h"

namespace cr {

namespace {

size_t non_finite(const LutImage& img) { return count_non_finite(img.texels); }

size_t non_finite_luts(const LutScheduler& s) {
  size_t n = non_finite(s.transmittance()->image());
  const MultiScatteringLut& ms = *s.multiscattering();
  n += non_finite(ms.image());
  for (int k = 0; k < kMsMomentCount; ++k) n += non_finite(ms.moment_image(k));
  if (s.skyview()) n += non_finite(s.skyview()->image()) + non_finite(s.skyview()->mie_image());
  if (s.aerial_perspective())
    n += non_finite(s.aerial_perspective()->luminance()) + non_finite(s.aerial_perspective()->transmittance());
  return n;
}

}  // namespace

AtmosphereModel with_density_scale(AtmosphereModel model, float scale) {
  model.rayleigh_scattering *= scale;
  model.mie_scattering *= scale;
  model.mie_absorption *= scale;
  model.ozone_absorption *= scale;
  return model;
}

SkyStabilityCell evaluate_sky_stability(const AtmosphereModel& model, const AtmosphereSettings& settings,
                                        double sun_zenith_deg, double altitude, const SkyStabilityOptions& options,
                                        JobSystem& jobs) {
  SkySetup setup;
  setup.scene.model = model;
  setup.settings = settings;
  AtmosphereSettings full = settings;
  full.full_schedule = true;  // every LUT for this camera and sun, as the plugin's first frame builds them
  SkyCase c = make_sky_case(setup, full);
  const glm::vec3 sun = sun_at_zenith_angle(sun_zenith_deg);
  const glm::vec3 e = solar_sun_illuminance();
  const int w = options.width, h = options.height;
  const double t0 = now_ms();
  update_sky_case(c, 0, horizon_camera(altitude, 16, 9), sun, e, jobs);
  const bool from_space = c.plan.space;
  const std::vector<glm::vec3> dirs = accuracy_panorama(w, h, from_space);
  std::vector<glm::vec3> sky(dirs.size()), geometry(dirs.size(), glm::vec3(0.0f));
  // The ground seen in the panorama, grey, through aerial perspective: the
  // froxel LUT below the space altitude, the per-pixel march above it.
  const double r = c.frame.camera_radius, ground = c.frame.model.bottom_radius;
  jobs.parallel_for("atmosphere.stability", dirs.size(), 16, [&](size_t b, size_t en) {
    for (size_t i = b; i < en; ++i) {
      sky[i] = sky_radiance(c.frame, dirs[i], false);
      const double t = distance_to_ground(r, glm::dot(dirs[i], c.frame.up), ground);
      if (t >= 0.0) geometry[i] = apply_aerial_perspective(c.frame, dirs[i], float(t), glm::vec3(0.18f));
    }
  });
  SkyStabilityCell cell;
  cell.lut_ms = now_ms() - t0;
  const LutScheduler& luts = *c.luts;
  cell.space = from_space;
  cell.non_finite_luts = non_finite_luts(luts);
  cell.non_finite_sky = count_non_finite(sky);
  cell.non_finite_geometry = count_non_finite(geometry);
  const MultiScatteringLut& ms = *luts.multiscattering();
  cell.ms_texels = ms.texel_count();
  cell.ms_clamped = size_t(ms.clamped_texels());
  cell.max_fms = ms.max_fms_seen();
  cell.explicit_orders = ms.explicit_orders();
  for (const ExplicitOrderChoice& o : luts.multiscattering_orders()) cell.orders_capped |= o.capped;
  const LutImage& t = luts.transmittance()->image();
  cell.transmittance_texels = t.count();
  for (const glm::vec3& v : t.texels) cell.transmittance_underflow += (v.x == 0.0f || v.y == 0.0f || v.z == 0.0f);
  if (!options.reference) return cell;

  ReferenceSettings rs;
  rs.samples_per_pixel = options.spp;
  rs.seed = options.seed;
  rs.sampling = options.sampling;
  ReferenceView view;
  view.origin = glm::dvec3(0.0, ground + altitude, 0.0);
  view.directions = dirs;
  view.sun_direction = sun;
  view.sun_illuminance = e;
  const double r0 = now_ms();
  const ReferenceImage ref = render_reference(c.frame.model, view, rs, jobs, {});
  cell.ref_ms = now_ms() - r0;
  cell.non_finite_reference = count_non_finite(ref.radiance) + count_non_finite(ref.noise);
  std::vector<float> sky_y(dirs.size()), ref_y(dirs.size());
  for (size_t i = 0; i < dirs.size(); ++i) {
    sky_y[i] = luminance(sky[i]);
    ref_y[i] = luminance(ref.radiance[i]);
  }
  cell.score = score_accuracy(sky_y, ref_y, ref.noise, scored_sky(c.frame, dirs, from_space));
  return cell;
}

}  // namespace cr

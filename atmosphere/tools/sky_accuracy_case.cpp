#include "atmosphere/tools/sky_accuracy_case.h"

#include "atmosphere/sky_composite.h"
#include "engine/core/luminance.h"

namespace cr {

SkyLutPanorama render_lut_panorama(const SkySetup& setup, const AtmosphereSettings& settings, double altitude,
                                   const glm::vec3& sun, int width, int height, JobSystem& jobs) {
  AtmosphereSettings full = settings;
  full.full_schedule = true;
  SkyLutPanorama p;
  p.from_space = altitude > full.space_altitude;
  p.directions = accuracy_panorama(width, height, p.from_space);
  p.sky = make_sky_case(setup, full);
  const double t0 = now_ms();
  update_sky_case(p.sky, 0, horizon_camera(altitude, 16, 9), sun, solar_sun_illuminance(), jobs);
  p.radiance.resize(p.directions.size());
  jobs.parallel_for("atmosphere.accuracy", p.directions.size(), 64, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) p.radiance[i] = sky_radiance(p.sky.frame, p.directions[i], false);
  });
  p.ms = now_ms() - t0;
  return p;
}

ReferenceView reference_panorama_view(const SkySetup& setup, const SkyLutPanorama& lut, double altitude,
                                      const glm::vec3& sun) {
  ReferenceView view;
  view.origin = glm::dvec3(0.0, lut.sky.frame.model.bottom_radius + setup.scene.ground_altitude + altitude, 0.0);
  view.directions = lut.directions;
  view.sun_direction = sun;
  view.sun_illuminance = solar_sun_illuminance();
  return view;
}

ReferenceLuminance reference_luminance(const ReferenceImage& ref) {
  ReferenceLuminance r;
  r.luminance = luminances(ref.radiance);
  r.noise = ref.noise;
  for (const glm::vec3& c : ref.radiance) r.color.insert(r.color.end(), {c.r, c.g, c.b});
  for (const glm::vec2& n : ref.ratio_noise) r.ratio_noise.insert(r.ratio_noise.end(), {n.x, n.y});
  return r;
}

std::vector<float> luminances(const std::vector<glm::vec3>& radiance) {
  std::vector<float> y(radiance.size());
  for (size_t i = 0; i < radiance.size(); ++i) y[i] = luminance(radiance[i]);
  return y;
}

}  // namespace cr

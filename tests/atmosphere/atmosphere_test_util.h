#pragma once
// Small LUT settings and a camera/sun setup shared by the atmosphere tests.
#include <cmath>

#include "atmosphere/lut_scheduler.h"
#include "atmosphere/planet_frame.h"
#include "atmosphere/sky_frame.h"
#include "engine/core/math_constants.h"

namespace cr::test {

// Small LUTs: the tests check behaviour, not the desktop resolution (fast under sanitizers too).
inline AtmosphereSettings small_settings() {
  AtmosphereSettings s;
  s.transmittance_width = 64;
  s.transmittance_height = 16;
  s.transmittance_steps = 20;
  s.multiscattering_width = 8;
  s.multiscattering_height = 8;
  s.multiscattering_directions = 16;
  s.multiscattering_steps = 8;
  s.skyview_width = 24;
  s.skyview_height = 16;
  s.skyview_max_steps = 8;
  s.ap_width = 8;
  s.ap_height = 8;
  s.ap_depth = 8;
  return s;
}

inline glm::vec3 sun_from_zenith(double deg) {
  const double z = deg * kPiD / 180.0;
  return glm::vec3(float(std::sin(z)), float(std::cos(z)), 0.0f);
}

inline Camera camera_at(double altitude, double x = 0.0, double yaw_deg = 0.0) {
  const double yaw = yaw_deg * kPiD / 180.0;
  return Camera::look_at(glm::dvec3(x, altitude, 0.0),
                         glm::dvec3(x + 1000.0 * std::cos(yaw), altitude - 20.0, 1000.0 * std::sin(yaw)), 1.0471976f,
                         16.0f / 9.0f, 0.1f);
}

inline AtmosphereSceneConfig scene_config(const AtmosphereModel& m = AtmosphereModel()) {
  AtmosphereSceneConfig c;
  c.model = m;
  return c;
}

// Plans and runs one frame; returns the plan.
inline AtmospherePlan run_frame(LutScheduler& s, int frame, const Camera& cam, const glm::vec3& sun, JobSystem& jobs) {
  AtmosphereSceneConfig c = scene_config(s.model());
  const AtmospherePlan p = s.plan(frame_inputs(s.model(), planet_offset(c), frame, cam, sun));
  s.run_all(p, jobs);
  return p;
}

inline SkyFrame frame_of(const LutScheduler& s, const AtmospherePlan& p, const Camera& cam) {
  return make_sky_frame(s, p, cam, planet_offset(scene_config(s.model())), glm::vec3(110000.0f));
}

}  // namespace cr::test

#include "atmosphere/sky_frame.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"

namespace cr {

namespace {
// Linear limb-darkening coefficients u of I(mu)/I(1) = 1 - u (1 - mu), per
// channel (red darkens least); approximate solar values in the visible.
const glm::vec3 kLimbDarkening(0.55f, 0.65f, 0.75f);
}  // namespace

SkyFrame make_sky_frame(const LutScheduler& luts, const AtmospherePlan& plan, const Camera& camera,
                        const glm::dvec3& planet_offset, const glm::vec3& sun_illuminance) {
  SkyFrame f;
  f.transmittance = luts.transmittance();
  f.multiscattering = luts.multiscattering();
  f.ms_transmittance = luts.multiscattering_source();
  f.skyview = luts.skyview();
  f.aerial_perspective = luts.aerial_perspective();
  f.space = plan.space;
  f.valid = f.transmittance && f.multiscattering && f.skyview && (f.space || f.aerial_perspective);
  f.model = f.transmittance ? f.transmittance->model() : luts.model();
  const AtmosphereSettings& s = luts.settings();
  f.fixed = s.composite_precision == CompositePrecision::Fixed;
  f.space_steps = s.space_steps;
  f.skyview_min_steps = s.skyview_min_steps;
  f.skyview_max_steps = s.skyview_max_steps;

  f.camera = camera;
  f.planet_offset = planet_offset;
  f.camera_position = camera.position + planet_offset;
  const double r = glm::length(f.camera_position);
  f.up = r > 0.0 ? glm::vec3(f.camera_position / r) : glm::vec3(0.0f, 1.0f, 0.0f);
  // Below the ground (camera in terrain / under sea level): clamp to the ground.
  f.camera_radius = std::max(r, f.model.bottom_radius);
  f.camera_altitude = float(f.camera_radius - f.model.bottom_radius);
  f.sun = plan.inputs.camera.sun_direction;
  f.mu_s = std::clamp(glm::dot(f.sun, f.up), -1.0f, 1.0f);
  const glm::vec3 horizontal = f.sun - f.mu_s * f.up;
  const float len = glm::length(horizontal);
  if (len > 1e-6f) {
    f.sun_horizontal = horizontal / len;
  } else {  // sun at the zenith or nadir: every azimuth is the same, pick any tangent
    const glm::vec3 ref = std::abs(f.up.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    f.sun_horizontal = glm::normalize(ref - glm::dot(ref, f.up) * f.up);
  }
  f.mu_horizon = float(horizon_mu(f.camera_radius, f.model.bottom_radius));
  f.sun_illuminance = sun_illuminance;
  if (f.transmittance) f.camera_row = f.transmittance->row(f.camera_altitude);

  const float alpha = f.model.sun_angular_radius;
  f.cos_sun_radius = std::cos(alpha);
  const float solid_angle = 2.0f * kPi * (1.0f - f.cos_sun_radius);
  f.sun_disk_center = sun_illuminance / solid_angle / (glm::vec3(1.0f) - kLimbDarkening / 3.0f);
  return f;
}

glm::vec3 sun_disk_limb(const glm::vec3& center, float mu_disk) {
  return center * (glm::vec3(1.0f) - kLimbDarkening * (1.0f - mu_disk));
}

}  // namespace cr

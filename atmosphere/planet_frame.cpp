#include "atmosphere/planet_frame.h"

#include <cmath>

namespace cr {

glm::dvec3 planet_offset(const AtmosphereSceneConfig& config) {
  return glm::dvec3(0.0, config.model.bottom_radius + config.ground_altitude, 0.0);
}

AtmosphereFrameInputs frame_inputs(const AtmosphereModel& model, const glm::dvec3& offset, int frame,
                                   const Camera& camera, const glm::vec3& sun_direction) {
  AtmosphereFrameInputs in;
  in.frame = frame;
  in.ground_radius = model.bottom_radius;
  in.camera.position = camera.position + offset;
  in.camera.forward = camera.forward;
  in.camera.up = camera.up;
  in.camera.right = camera.right;
  in.camera.tan_half_fov = std::tan(0.5f * camera.vfov_rad);
  in.camera.aspect = camera.aspect;
  const float len = glm::length(sun_direction);
  in.camera.sun_direction = len > 0.0f ? sun_direction / len : glm::vec3(0.0f, 1.0f, 0.0f);
  return in;
}

}  // namespace cr

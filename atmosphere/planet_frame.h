#pragma once
// World space (glTF metres, +Y up, y = 0 is the ground at ground_altitude_m)
// to the planet-centred frame the atmosphere computes in: the planet centre is
// at (0, -(R + ground_altitude), 0), so planet-centred = world + offset, in double.
#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/lut_scheduler.h"
#include "engine/scene/camera.h"

namespace cr {

glm::dvec3 planet_offset(const AtmosphereSceneConfig& config);

// The scheduler's inputs for a camera and sun direction.
AtmosphereFrameInputs frame_inputs(const AtmosphereModel& model, const glm::dvec3& planet_offset, int frame,
                                   const Camera& camera, const glm::vec3& sun_direction);

}  // namespace cr

#pragma once
// A synthetic fog setup without a scene, for fog-stability and the tests:
// light from a sun and a constant sky, and a shadow map of a tall thin wall
// at x in [-1, 1] (all z) whose shadow edge makes a light shaft.
#include <glm/glm.hpp>

#include "engine/scene/camera.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"

namespace cr {

LightEnvironment synthetic_light(const glm::vec3& sun_dir, float sun_lux, float ambient);

// The shadow map over the region around the origin, fitted to `cam`, with
// the wall (0 to wall_height metres high) as the only occluder.
ShadowMap wall_shadow_map(const Camera& cam, const glm::vec3& sun_dir, float wall_height = 40.0f);

}  // namespace cr

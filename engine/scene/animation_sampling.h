#pragma once
// Values of a glTF animation sampler at a time, as the glTF 2.0 spec
// interpolates them: STEP holds a key's value, LINEAR interpolates linearly
// (rotations by spherical linear interpolation along the shorter arc), and
// CUBICSPLINE is the cubic Hermite spline through the keys with the file's
// tangents scaled by the key interval. Before the first key the first value
// holds, after the last the last.
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/scene_animation.h"

namespace cr {

// The sampler's `components` values at `time_s`.
std::vector<double> sample_values(const AnimationSampler& sampler, double time_s);

// A rotation sampler's (components 4: x, y, z, w) unit quaternion at `time_s`.
glm::dquat sample_rotation(const AnimationSampler& sampler, double time_s);

}  // namespace cr

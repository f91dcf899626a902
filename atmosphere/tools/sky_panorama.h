#pragma once
// The panoramas the sky's accuracy is measured on, and which of their pixels
// are scored: sky-accuracy and sky-stability view the same directions.
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/sky_frame.h"

namespace cr {

// Directions: azimuth 0..360 deg from the sun's azimuth (+X), elevation top_deg .. bottom_deg.
std::vector<glm::vec3> panorama(int width, int height, double top_deg, double bottom_deg);
// The measured view: elevation 90 to -10 deg; from space (the space fallback), the planet and its limb, 0 to -90.
std::vector<glm::vec3> accuracy_panorama(int width, int height, bool from_space);
// Scored: sky above the horizon; from space, every direction that meets the atmosphere.
std::vector<bool> scored_sky(const SkyFrame& frame, const std::vector<glm::vec3>& dirs, bool from_space);

}  // namespace cr

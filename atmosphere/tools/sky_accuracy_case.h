#pragma once
// One case of sky-accuracy, shared with sweep --truth: the accuracy panorama
// seen from `altitude` metres above the ground under a unit `sun` (whose
// azimuth is the panorama's 0), by the LUT method and as the path-traced
// reference's view, both lit by the solar spectrum's sun.
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/tools/reference_merge.h"
#include "atmosphere/tools/reference_renderer.h"
#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_panorama.h"

namespace cr {

struct SkyLutPanorama {
  std::vector<glm::vec3> directions;
  bool from_space = false;  // above the space fallback altitude: the planet and its limb
  SkyCase sky;              // the LUTs and frame state it was rendered with
  std::vector<glm::vec3> radiance;
  double ms = 0.0;  // the LUTs' work and the panorama's
  std::vector<bool> scored() const { return scored_sky(sky.frame, directions, from_space); }
};
// `settings`' LUTs, rebuilt in full (a single view has no schedule to amortise).
SkyLutPanorama render_lut_panorama(const SkySetup& setup, const AtmosphereSettings& settings, double altitude,
                                   const glm::vec3& sun, int width, int height, JobSystem& jobs);
// The reference's view of the same panorama.
ReferenceView reference_panorama_view(const SkySetup& setup, const SkyLutPanorama& lut, double altitude,
                                      const glm::vec3& sun);
// A rendered reference's luminance, noise, colour and colour-ratio noise, as stored references have them.
ReferenceLuminance reference_luminance(const ReferenceImage& ref);
std::vector<float> luminances(const std::vector<glm::vec3>& radiance);

}  // namespace cr

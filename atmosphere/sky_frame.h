#pragma once
// Everything the per-pixel composite and the lighting need in one frame: the
// published LUTs (shared, so a rebuild publishing mid-frame cannot pull them
// away) and per-frame constants in the planet-centred frame.
#include <memory>

#include <glm/glm.hpp>

#include "atmosphere/aerial_perspective_lut.h"
#include "atmosphere/lut_scheduler.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/skyview_lut.h"
#include "atmosphere/transmittance_lut.h"
#include "engine/scene/camera.h"

namespace cr {

struct SkyFrame {
  bool valid = false;
  bool space = false;  // camera above the space altitude: sky-view LUT seen from space, geometry ray marched
  // "composite": "fixed": the sky-view and froxel LUTs are sampled from their
  // q15 texels in 16-bit integer arithmetic (SkyViewLut::sample_fixed).
  bool fixed = false;
  AtmosphereModel model;
  std::shared_ptr<const TransmittanceLut> transmittance;       // latest, for the sun
  std::shared_ptr<const TransmittanceLut> ms_transmittance;    // the one the MS LUT was built from
  std::shared_ptr<const MultiScatteringLut> multiscattering;
  std::shared_ptr<const SkyViewLut> skyview;
  std::shared_ptr<const AerialPerspectiveLut> aerial_perspective;

  Camera camera;              // world-space camera of the frame
  glm::dvec3 planet_offset;   // world -> planet-centred: p + planet_offset
  glm::dvec3 camera_position; // planet-centred
  double camera_radius = 0.0; // clamped to >= ground radius
  float camera_altitude = 0.0f;
  glm::vec3 up{0.0f, 1.0f, 0.0f};   // local vertical at the camera
  glm::vec3 sun{0.0f, 1.0f, 0.0f};  // towards the sun
  glm::vec3 sun_horizontal{1.0f, 0.0f, 0.0f};  // the sun's azimuth in the local tangent plane
  float mu_s = 1.0f;
  float mu_horizon = 0.0f;    // rays below hit the ground
  glm::vec3 sun_illuminance{0.0f};  // unattenuated, RGB lux
  TransmittanceRow camera_row{};
  float cos_sun_radius = 1.0f;
  glm::vec3 sun_disk_center{0.0f};  // radiance at the disk centre (limb darkening normalised)
  int space_steps = 24;
  int skyview_min_steps = 4;
  int skyview_max_steps = 14;
};

// Builds the frame state from the scheduler's published LUTs.
SkyFrame make_sky_frame(const LutScheduler& luts, const AtmospherePlan& plan, const Camera& camera,
                        const glm::dvec3& planet_offset, const glm::vec3& sun_illuminance);

// Limb-darkened disk radiance at mu_disk = cos of the angle on the solar surface
// (1 at the centre, 0 at the limb), from the centre radiance.
glm::vec3 sun_disk_limb(const glm::vec3& center, float mu_disk);

}  // namespace cr

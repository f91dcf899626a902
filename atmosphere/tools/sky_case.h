#pragma once
// What the sky commands share: the atmosphere they measure (--preset or
// --scene, --profile), and a sky case: LUTs on a scheduler and the frame state
// seen from one camera under one sun.
#include <memory>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_plugin.h"
#include "atmosphere/lut_scheduler.h"
#include "atmosphere/sky_frame.h"
#include "engine/cli/arg_parser.h"
#include "engine/core/job_system.h"
#include "engine/scene/camera.h"

namespace cr {

struct SkySetup {
  AtmosphereSceneConfig scene;
  AtmosphereSettings settings;
};

// Declares --preset, --scene, --profile and --threads.
void add_sky_setup_options(ArgParser& p);
// --scene FILE (its "atmosphere" section) or --preset NAME; --profile FILE (its "atmosphere" section).
SkySetup load_sky_setup(const ArgParser& p);

// The LUTs and frame state of one view.
struct SkyCase {
  std::unique_ptr<LutScheduler> luts;
  AtmospherePlan plan;
  SkyFrame frame;
  Camera camera;
  glm::dvec3 offset;
};
SkyCase make_sky_case(const SkySetup& setup, const AtmosphereSettings& settings);
// Plans and runs the LUT work of `frame` for this camera and sun, then builds the frame state.
void update_sky_case(SkyCase& c, int frame, const Camera& camera, const glm::vec3& sun, const glm::vec3& illuminance,
                     JobSystem& jobs);

// The camera path sky-bench and sky-environment measure schedules along: from
// `altitude`, 3 m forward and 0.5 m up per frame, turning 0.2 deg per frame.
Camera path_camera(int frame, double altitude, float aspect);
// The sun along that path: setting 0.1 deg per frame from 30 deg (unit).
glm::vec3 path_sun(int frame);
// A camera `altitude` metres above the ground looking at the horizon towards +X (the sun's azimuth).
Camera horizon_camera(double altitude, int width, int height);
// The unit direction to a sun `zenith_deg` from the zenith, in the +X azimuth.
// The scene default's sun: the solar spectrum's illuminance and colour (engine/core/colorimetry.h).
glm::vec3 solar_sun_illuminance();
glm::vec3 sun_at_zenith_angle(double zenith_deg);
double now_ms();  // a steady clock

}  // namespace cr

#pragma once
// The sky as a prefiltered specular environment (engine/shading/
// environment_prefilter.h) for glossy reflections, with its own amortised
// schedule, published to the shading through LightEnvironment::specular.
//
// Radiance: sky_radiance(f, dir, false) over the whole sphere (sky-view LUT,
// no sun disk: the sun's specular is the analytic direct term). Below the
// horizon the sky-view LUT already holds the sun-lit ground: its rays end on
// the ground, which adds albedo * (T_sun E_sun mu / pi + Psi_ms E_sun) seen
// through the ray's transmittance, with the in-scatter in front of it
// (scattering_march.cpp, ground_luminance; Psi_ms at the ground stands for
// the sky irradiance / pi). So nothing is added here; `sky-environment`
// checks that ground against albedo / pi * (transmitted sun + the SH sky
// irradiance).
//
// Schedule (like a LUT's in lut_scheduler.h, with its own period and slices):
//   initial   - nothing published yet: baked whole in the first frame
//   upstream  - the atmosphere changed (its multi-scattering LUT republished)
//   sun       - the sun turned more than invalidation.sun_deg (its direction:
//               the environment is in world directions, azimuth included)
//   camera    - the camera's altitude moved more than invalidation.camera_m,
//               or its local vertical turned more than camera_deg
//   periodic  - `period` frames since the last start and the inputs drifted
//   full      - the "full" schedule: baked whole every frame
// A rebuild snapshots the frame's SkyFrame (its LUTs are shared) and bakes
// slice by slice into a back buffer; the front is replaced when the last
// slice is done, so shading always sees a complete environment. Unlike the
// LUTs, an invalidation during a rebuild does not restart it: a restart per
// 0.5 degrees of sun would starve a sliced rebuild under a fast sun; the
// next rebuild starts when this one publishes.
#include <cstdint>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/lut_scheduler.h"
#include "atmosphere/sky_frame.h"
#include "engine/core/job_system.h"
#include "engine/shading/environment_prefilter.h"

namespace cr {

// The sky's radiance (cd/m^2, no sun disk) for the prefilter.
EnvironmentPrefilter::Radiance sky_environment_radiance(const SkyFrame& f);
// The environment of one sky frame, baked whole.
std::shared_ptr<const SpecularEnvironment> bake_sky_environment(const SkyFrame& f, const AtmosphereSettings& s,
                                                                JobSystem& jobs);

struct EnvironmentWork {
  bool active = false;
  bool restart = false;
  int slice = 0;      // slice baked this frame
  int slices = 1;
  bool publishes = false;
  std::string cause;  // see above; "" when idle
};

class SkyEnvironment {
 public:
  explicit SkyEnvironment(const AtmosphereSettings& settings);

  // This frame's work, from the LUT plan's inputs and `upstream` (the
  // multi-scattering LUT's version once this frame's LUT work is done); changes no state.
  EnvironmentWork plan(const AtmospherePlan& plan, uint64_t upstream) const;
  // Runs it; a restart snapshots `sky` (this frame's, built from the same plan).
  void run(const EnvironmentWork& w, const AtmospherePlan& plan, uint64_t upstream, const SkyFrame& sky,
           JobSystem& jobs);

  std::shared_ptr<const SpecularEnvironment> front() const { return front_; }
  uint64_t version() const { return version_; }
  double frame_ms() const { return frame_ms_; }
  double full_ms() const { return full_ms_; }
  // Report fields: updated, cause, slice, published, age (frames since the
  // front's inputs), times (this frame, full rebuild, amortised over the period), sizes.
  nlohmann::json report(const EnvironmentWork& w, int frame) const;

 private:
  struct Inputs {
    int frame = 0;
    glm::vec3 sun{0.0f};
    glm::dvec3 up{0.0};
    double altitude = 0.0;
    uint64_t upstream = 0;
  };
  static Inputs inputs_of(const AtmospherePlan& plan, uint64_t upstream);
  std::string invalidation(const Inputs& now) const;

  AtmosphereSettings settings_;
  std::shared_ptr<const SpecularEnvironment> front_;
  Inputs front_inputs_;
  uint64_t version_ = 0;
  // The rebuild in progress.
  std::unique_ptr<EnvironmentPrefilter> back_;
  std::unique_ptr<SkyFrame> back_sky_;
  Inputs back_inputs_;
  int next_slice_ = 0;
  int slices_ = 1;
  std::string back_cause_;
  double frame_ms_ = 0.0, building_ms_ = 0.0, full_ms_ = 0.0;
};

}  // namespace cr

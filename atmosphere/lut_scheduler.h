#pragma once
// The amortised update scheduler of the four LUTs.
//
// Dependency graph (an arrow: "is an input of"):
//
//   atmosphere parameters --> transmittance --> multi-scattering --+--> sky-view <-- camera altitude, sun zenith
//                                                                  +--> aerial perspective <-- camera pose, sun direction
//
// Each LUT keeps a published ("front") version, which is what passes sample,
// and, while a rebuild is in progress, a private back buffer filled slice by
// slice (a rebuild of k slices touches 1/k of the texels per frame), so a
// half-updated LUT is never visible. A rebuild starts when:
//   initial   - nothing published yet (built whole, in one frame)
//   params    - the atmosphere parameters changed (transmittance)
//   upstream  - the LUT it was built from was republished
//   sun       - the sun moved more than invalidate_sun_deg (sky-view: zenith angle; AP: direction)
//   camera    - the camera moved more than invalidate_camera_m / turned more than invalidate_camera_deg
//   periodic  - `period` frames since the last start and the inputs drifted at all (below the thresholds)
//   full      - the "full" schedule rebuilds all four every frame
// Invalidation while a rebuild is in progress restarts it with the new inputs.
// Unchanged inputs never trigger work. In the space fallback (camera above
// space_altitude) the AP LUT is not built (geometry is ray marched per pixel)
// and the sky-view LUT is built for the camera's true altitude (seen from space).
// Each rebuild snapshots its inputs and upstream LUTs when it starts, so all of
// its slices see the same inputs and its result is bit-identical to a one-shot build.
//
// With "spectral_samples" above 3 every LUT is baked once per group of three
// wavelengths (each group's chain reads its own upstream LUTs) and the
// published LUT is the groups mixed into RGB (spectral_mix.h); the schedule,
// slicing and invalidation are the same for all groups.
#include <array>
#include <functional>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "atmosphere/aerial_perspective_lut.h"
#include "atmosphere/atmosphere_model.h"
#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/skyview_lut.h"
#include "atmosphere/spectral_sampling.h"
#include "atmosphere/transmittance_lut.h"
#include "engine/core/job_system.h"

namespace cr {

// What the LUTs depend on in one frame (planet-centred, metres).
struct AtmosphereFrameInputs {
  int frame = 0;
  FroxelCamera camera;  // position relative to the planet centre, orientation, sun direction
  double ground_radius = 6360e3;
  double altitude() const;   // camera altitude above the ground sphere (may be negative)
  double radius() const;
};

// What one LUT does in one frame.
struct LutWork {
  bool active = false;   // bakes a slice this frame
  bool restart = false;  // starts a new rebuild (snapshotting inputs)
  int slice = 0;         // first slice baked this frame
  int slice_end = 0;     // one past the last slice baked this frame
  int slices = 1;
  bool publishes = false;
  std::string cause;     // why the rebuild runs (see the header comment); "" when idle
};

struct AtmospherePlan {
  int frame = 0;
  AtmosphereFrameInputs inputs;
  bool space = false;  // camera above space_altitude: per-pixel ray marching
  std::array<LutWork, kLutKinds> work;
};

class LutScheduler {
 public:
  // The sampling is lut_sampling(settings.spectral_samples) unless given.
  explicit LutScheduler(const AtmosphereSettings& settings);
  LutScheduler(const AtmosphereSettings& settings, SpectralSampling sampling);

  // Sets the atmosphere; a different model invalidates the transmittance LUT.
  void set_model(const AtmosphereModel& model);
  const AtmosphereModel& model() const { return model_; }
  const AtmosphereSettings& settings() const { return settings_; }
  const SpectralSampling& sampling() const { return sampling_; }

  // Decides this frame's work; changes no state.
  AtmospherePlan plan(const AtmosphereFrameInputs& inputs) const;
  // Runs one LUT's work of the plan; call in dependency order (transmittance,
  // multi-scattering, then sky-view and AP in any order or concurrently).
  void run(LutKind kind, const AtmospherePlan& plan, JobSystem& jobs);
  void run_all(const AtmospherePlan& plan, JobSystem& jobs);  // all four, in order

  // Published LUTs (null before the first publish).
  std::shared_ptr<const TransmittanceLut> transmittance() const { return t_.front; }
  std::shared_ptr<const MultiScatteringLut> multiscattering() const { return ms_.front; }
  std::shared_ptr<const TransmittanceLut> multiscattering_source() const { return ms_.built_from; }
  std::shared_ptr<const SkyViewLut> skyview() const { return sv_.front; }
  std::shared_ptr<const AerialPerspectiveLut> aerial_perspective() const { return ap_.front; }
  uint64_t version(LutKind kind) const;  // publish count
  // The explicit orders each wavelength group's multi-scattering LUT was
  // chosen (empty before the first multi-scattering rebuild).
  const std::vector<ExplicitOrderChoice>& multiscattering_orders() const { return ms_orders_; }

  // Figures of the last frame for the report (see report_frame).
  nlohmann::json report(const AtmospherePlan& plan) const;
  double frame_ms(LutKind kind) const { return timing_[size_t(kind)].frame_ms; }
  double full_ms(LutKind kind) const { return timing_[size_t(kind)].full_ms; }

 private:
  struct Timing {
    double frame_ms = 0.0;    // work this frame
    double building_ms = 0.0; // sum over the slices of the rebuild in progress
    double full_ms = 0.0;     // all slices of the last completed rebuild
    double total_ms = 0.0;    // everything since start (for the running average)
    int frames = 0;
  };
  template <class Lut>
  struct Slot {
    std::shared_ptr<const Lut> front;  // published (RGB: the groups mixed)
    std::vector<std::shared_ptr<const Lut>> front_groups;  // per wavelength group (RGB: front itself)
    uint64_t version = 0;
    std::vector<std::shared_ptr<Lut>> back;  // the rebuild in progress, per group; empty when idle
    int next_slice = 0;
    int slices = 1;
    int last_start = -1000000;
    // Inputs of the front (f_*) and of the rebuild in progress (b_*).
    uint64_t f_upstream = 0, b_upstream = 0;
    FroxelCamera f_camera, b_camera;
    float f_altitude = 0.0f, b_altitude = 0.0f;
    // Upstream snapshots: the mixed transmittance (for the consumers of the
    // front) and each group's upstream LUTs (for the group bakes).
    std::shared_ptr<const TransmittanceLut> built_from, b_t_mixed;
    std::vector<std::shared_ptr<const TransmittanceLut>> built_from_groups, b_t;
    std::vector<std::shared_ptr<const MultiScatteringLut>> b_ms;
    std::string b_cause;
  };

  std::vector<AtmosphereModel> group_models(const AtmosphereModel& model) const;
  LutWork decide(LutKind kind, const AtmosphereFrameInputs& in, bool space, const AtmospherePlan& so_far) const;
  std::string invalidation(LutKind kind, const AtmosphereFrameInputs& in, bool against_back,
                           uint64_t upstream_version) const;
  bool drifted(LutKind kind, const AtmosphereFrameInputs& in) const;
  void run_slices(LutKind kind, size_t items, size_t granule, int slice, int slice_end, int slices,
                  JobSystem& jobs, const std::function<void(size_t, size_t)>& bake);

  AtmosphereSettings settings_;
  SpectralSampling sampling_;
  AtmosphereModel model_;
  std::vector<AtmosphereModel> group_models_;  // model_ at each group's wavelengths
  uint64_t model_version_ = 1;
  // The multi-scattering LUT's explicit orders and the atmosphere they were chosen for.
  std::vector<ExplicitOrderChoice> ms_orders_;  // per group
  std::vector<std::optional<AtmosphereModel>> ms_orders_model_;
  Slot<TransmittanceLut> t_;
  Slot<MultiScatteringLut> ms_;
  Slot<SkyViewLut> sv_;
  Slot<AerialPerspectiveLut> ap_;
  std::array<Timing, kLutKinds> timing_{};
  int last_frame_ = -1;
};

// Slice `s` of `slices` over `items`, aligned down to multiples of `granule`.
size_t slice_begin(size_t items, size_t granule, int s, int slices);

// The explicit orders an atmosphere needs at the profile's settings
// (explicit_orders_for: ~1 ms, so once per atmosphere, not per bake), and
// the multi-scattering LUT with them.
ExplicitOrderChoice explicit_orders_for(const AtmosphereModel& model, const AtmosphereSettings& s);
std::shared_ptr<MultiScatteringLut> new_multiscattering_lut(const AtmosphereModel& model, const AtmosphereSettings& s,
                                                            int explicit_orders);

// lut.bake(begin, end) as jobs of `granule` items, one parallel_for per pass
// it spans (a pass needs all of the previous one).
void bake_in_jobs(MultiScatteringLut& lut, size_t begin, size_t end, size_t granule, const TransmittanceLut& t,
                  JobSystem& jobs, const std::string& name);

}  // namespace cr

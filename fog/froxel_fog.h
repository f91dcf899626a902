#pragma once
// The froxel fog of one view over time: settings, the grid, the per-frame
// froxel buffers and the double-buffered history. The plugin runs its steps as
// frame-graph passes; tests and commands run them directly. Steps of a frame
// run in order: begin_frame, density, lighting, reproject, filter, integrate,
// then composite (any pixel rectangles, concurrently). density plans the
// voxelisation (volume footprints); lighting writes the density of each row
// of columns right before it lights the row, so the row is read from cache
// (a view seen last frame keeps its density, and the lighting prefetches
// the row). How a frame uses its history is one FogRegime, decided once per
// frame (decide_regime): a still view lights until its jitter sequence is
// complete, then fades its history to the sequence's mean and freezes.
//
// With "precision": "fixed" the sun term is stored and blended as q15 codes
// (sun_term_format.h) and the integrated volume is FixedIntegratedFroxel
// (fixed_volume.h); the steps and regimes are the same.
#include <span>
#include <vector>

#include "engine/core/job_system.h"
#include "engine/render/frame_buffers.h"
#include "engine/render/plugin.h"
#include "engine/shading/light_environment.h"
#include "engine/shading/shadow_map.h"
#include "fog/fixed_volume.h"
#include "fog/fog_medium.h"
#include "fog/fog_settings.h"
#include "fog/froxel_passes.h"
#include "fog/jitter_sequence.h"

namespace cr {

struct FroxelFogStats {
  size_t lit_froxels = 0;     // froxels density, lighting and reprojection work on (after depth culling)
  size_t active_froxels = 0;  // froxels filter and integration produce
  VoxelizeStats voxelize;
  ReprojectStats reproject;
  bool history_used = false;
  bool light_changed = false;  // the sun moved since the history: light change measured
  int still_frames = 0;        // consecutive frames of a still view (same camera and sun) with history
  bool filtered = false;       // the 3x3 filter ran this frame
  bool density_kept = false;     // the same camera and lit froxels: last voxelisation kept
  bool jitter_complete = false;  // a still view with every jitter phase in: their mean replaces the lighting
  bool lighting_frozen = false;  // a converged still view: lighting and reprojection skipped
  bool volume_kept = false;      // ... and under the same light: integration skipped too
  size_t integrated_froxels = 0;  // froxels integration produced (a still view keeps the unchanged ones)
  size_t unsettled_froxels = 0;  // with still_settled, the froxels of the spans lit again (settled ones
                                 // between a column's first and last unsettled one included); else 0
};

// What the history is to a frame, and so what each step does with it. Along
// a still view that collects jitter phases the regimes run StillAccumulating,
// StillMean, Frozen; one that does not stays Still.
enum class FogRegime {
  NoHistory,  // no history to use (first frame, a cut or reset_history, reprojection off,
              // FrameView::history_valid false): this frame's light alone
  Moving,     // the history saw another camera or sun, or other lit or active froxels:
              // reprojected, clamped (profile), dropped where the light changed
  Still,      // the history's camera, sun and froxels, without collecting jitter phases
              // (still_accumulation off, several lighting samples a frame, or the density
              // voxelised anew): lit, blended by a running mean (with still_accumulation)
  StillAccumulating,  // ... collecting one sample per jitter phase: lit (with still_settled, only
                      // the unsettled froxels) and blended by a running mean, unclamped
  StillMean,  // ... every phase in: their mean stands in for the lighting, and reprojection
              // fades the rest of the history towards it
  Frozen,     // ... the history within 1/64 of that mean: lighting and reprojection skipped,
              // and integration too under the same light
};
// The history's camera, sun and froxels are this frame's (only the jitter differs).
constexpr bool is_still(FogRegime r) { return r >= FogRegime::Still; }

// The lighting integration applies: the scene's phase function, the light
// environment's sun and sky ambient, relative to the camera.
MediumLighting medium_lighting(const FogSceneSettings& scene, const LightEnvironment& light, const Camera& camera);

class FroxelFog {
 public:
  FroxelFog(const FogProfileSettings& profile, const FogSceneSettings& scene);

  // distance: the frame's per-pixel distance (FrameBuffers::distance) for
  // depth-aware culling; null keeps every froxel. The composite must then be
  // given the same distances.
  void begin_frame(const FrameView& view, JobSystem& jobs, const std::vector<float>* distance = nullptr);
  void density();
  // previous: last frame's shadow map (EngineResources::previous_shadow; size 0
  // or null when there is none). Where the sun has moved since, the history
  // is trusted less where the light changed (light_change_rejection).
  void lighting(const ShadowMap& shadow, JobSystem& jobs, const ShadowMap* previous = nullptr);
  void reproject(JobSystem& jobs);
  void filter(JobSystem& jobs);
  void integrate(const LightEnvironment& light, JobSystem& jobs);
  void composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) const;
  // The same for edge-pixel fragments, each at its own position and distance.
  void composite_fragments(std::span<EdgeFragment> fragments) const;
  // All steps but the composite, in order.
  void render(const FrameView& view, const LightEnvironment& light, const ShadowMap& shadow, JobSystem& jobs,
              const std::vector<float>* distance = nullptr, const ShadowMap* previous_shadow = nullptr);

  // Non-temporal supersampling: average n samples of the jitter sequence per
  // froxel in one frame (the many-sample result reprojection converges to).
  void set_lighting_samples(int n) { lighting_samples_ = n; }
  // Forgets the history (as after a camera cut).
  void reset_history() { have_history_ = false; }
  // This frame's regime, once lighting has run.
  FogRegime regime() const { return regime_; }

  const FogProfileSettings& profile() const { return profile_; }
  const FogSceneSettings& scene() const { return scene_; }
  const FogMedium& medium() const { return medium_; }
  const FroxelGrid& grid() const { return view_.grid; }
  const FroxelView& view() const { return view_; }
  const std::vector<FogDensity>& density_volume() const { return density_; }
  bool fixed_point() const { return profile_.precision == FogPrecision::Fixed; }
  // The sun visibility the integration uses (after reprojection and filter):
  // float, or q15 codes with fixed_point().
  const std::vector<float>& sun_visibility() const { return integration_input(float_); }
  const std::vector<uint16_t>& sun_visibility_q15() const { return integration_input(fixed_); }
  // Valid in each column's active slices (view().active_slices): the float
  // volume, or the fixed-point one with fixed_point().
  const std::vector<IntegratedFroxel>& volume() const { return volume_; }
  const std::vector<FixedIntegratedFroxel>& fixed_volume() const { return fixed_volume_; }
  // Froxel `index` of either volume as floats (the fixed-point one decoded).
  IntegratedFroxel integrated_froxel(size_t index) const {
    return fixed_point() ? decode_froxel(view_.grid, fixed_volume_, index) : volume_[index];
  }
  const FroxelFogStats& stats() const { return stats_; }

 private:
  // The sun term's buffers in one format: float, or q15 codes.
  template <class Value>
  struct SunBuffers {
    std::vector<Value> current;  // this frame's lighting
    std::vector<Value> light_change;  // valid this frame when light_changed_
    std::vector<Value> history[2];  // [current_] written this frame, the other read
    std::vector<Value> scratch, filtered;
    // The still run's samples, one per jitter phase (lit slices): their
    // sum, then, once every phase is in, their mean (q15: still_sum_ sums).
    std::vector<Value> still_mean;
    // For incremental integration in still views: the visibility the volume
    // was integrated from, saved when that frame was still.
    std::vector<Value> integrated_visibility;
  };
  template <class Value>
  const std::vector<Value>& blended(const SunBuffers<Value>& b) const {
    return blended_ < 0 ? b.current : b.history[blended_];
  }
  template <class Value>
  const std::vector<Value>& integration_input(const SunBuffers<Value>& b) const {
    return filter_now_ ? b.filtered : blended(b);
  }
  // The steps' work on one format's buffers (F: sun_term_format.h).
  template <class F>
  void light_in(SunBuffers<typename F::Value>& b, const ShadowMap& shadow, JobSystem& jobs, const ShadowMap* previous);
  template <class F>
  void reproject_in(SunBuffers<typename F::Value>& b, JobSystem& jobs);
  template <class Value, class Froxel>
  size_t integrate_in(SunBuffers<Value>& b, const MediumLighting& m, const std::vector<glm::vec3>& knots,
                      bool same_light, JobSystem& jobs, std::vector<Froxel>& volume);
  // The frame's regime and what follows from it (light change, still frames,
  // filter, stats), from the view, the density, the shadow maps and the
  // history: the one place a frame's treatment of its history is decided.
  void decide_regime(const ShadowMap& shadow, const ShadowMap* previous);
  // Adds this frame's sample to the still run's (once per jitter phase).
  template <class Value>
  void add_still_sample(SunBuffers<Value>& b, JobSystem& jobs);

  FogProfileSettings profile_;
  FogSceneSettings scene_;
  FogMedium medium_;
  FroxelView view_;
  int frame_ = 0;
  bool view_history_valid_ = false;  // this frame's FrameView::history_valid
  bool have_history_ = false;        // a blend is in the buffers' history[1 - current_] (reset_history forgets it)
  FogRegime regime_ = FogRegime::NoHistory;
  int lighting_samples_ = 1;
  DensityPlan density_plan_;
  std::vector<FogDensity> density_;
  // The view density_ was voxelised for (grid, camera and lit slices only).
  FroxelView density_view_;
  bool density_valid_ = false;  // density_ holds density_view_'s voxelisation
  bool density_kept_ = false;   // this frame's view is density_view_: no voxelisation
  SunBuffers<float> float_;
  SunBuffers<uint16_t> fixed_;
  std::vector<uint32_t> still_sum_;  // q15: the still run's sum of codes
  std::vector<SliceSpan> unsettled_;  // a still view's slices to light per column (settled_froxels.h)
  std::vector<uint64_t> settled_scratch_;
  // The sun moved since the history's shadow map (with light_change_rejection):
  // lighting measures the light change and reprojection drops history by it.
  // Decided with the regime; in practice Moving, as a moved sun ends a still view.
  bool light_changed_ = false;
  glm::vec3 history_sun_{0.0f};  // the last frame's shadow-map sun (0: no map)
  int current_ = 0;
  FroxelView history_view_;
  bool filter_now_ = false;  // the filter runs this frame: the buffers' filtered holds its output
  static constexpr int kMaxStillFrames = 1 << 16;  // the running mean's weight stops at 65536 / 65537
  int still_frames_ = 0;
  unsigned still_phases_ = 0;  // the jitter phases in the still run's samples (kAllPhases: their mean is complete)
  int still_samples_ = 0;  // in the sum (one covers every phase without jitter)
  static constexpr unsigned kAllPhases = (1u << kJitterFrames) - 1;
  // Once the mean is complete: the share of the history that is not the
  // mean (at most), fading by the history weight each frame; under
  // kFreezeShare the view is frozen.
  float fading_share_ = 1.0f;
  static constexpr float kFreezeShare = 1.0f / 64.0f;
  int blended_ = -1;  // the reprojection's output: history[blended_], or current when -1
  std::vector<IntegratedFroxel> volume_;
  std::vector<FixedIntegratedFroxel> fixed_volume_;
  // What volume_ was integrated from: stale once lighting (density and
  // visibility) runs again; the light and sun knots it was integrated under.
  bool volume_stale_ = true;
  MediumLighting integrated_light_;
  std::vector<glm::vec3> integrated_knots_;
  bool visibility_saved_ = false;  // the buffers' integrated_visibility holds the last still frame's
  FroxelFogStats stats_;
};

}  // namespace cr

#include "fog/froxel_fog.h"

#include <algorithm>
#include <type_traits>

#include "fog/settled_froxels.h"
#include "fog/sun_term_format.h"

namespace cr {

FroxelFog::FroxelFog(const FogProfileSettings& profile, const FogSceneSettings& scene)
    : profile_(resolve_fog_settings(profile, scene)), scene_(scene), medium_(scene) {}

void FroxelFog::begin_frame(const FrameView& view, JobSystem& jobs, const std::vector<float>* distance) {
  const FroxelGrid grid(view.width, view.height, profile_.froxel_size_px, profile_.slices, view.camera.znear,
                        profile_.fog_distance, profile_.slice_uniformity);
  // The last view's buffers are freed first, so the new view reuses that
  // memory instead of growing the heap (page faults every other frame).
  view_ = FroxelView{};
  view_ = make_froxel_view(grid, view.camera, jobs);
  if (distance) cull_froxels_by_depth(view_, *distance, jobs);
  medium_.set_camera(view.camera.position);
  frame_ = view.frame;
  view_history_valid_ = view.history_valid;
  stats_ = FroxelFogStats{};
  for (size_t c = 0; c < grid.columns(); ++c) {
    stats_.lit_froxels += view_.lit_slices[c];
    stats_.active_froxels += view_.active_slices[c];
  }
}

void FroxelFog::density() {
  // The medium is static: for the same camera and lit froxels the last
  // voxelisation is this frame's, bit for bit (a still view voxelises once).
  density_kept_ = density_valid_ && same_view(view_, density_view_) && view_.lit_slices == density_view_.lit_slices;
  stats_.density_kept = density_kept_;
  if (!density_kept_) {
    density_plan_ = plan_density(view_, medium_, profile_.density_samples);
    density_.resize(view_.grid.count());
    density_valid_ = false;  // until the lighting has voxelised it
    density_view_.grid = view_.grid;
    density_view_.camera = view_.camera;
    density_view_.lit_slices = view_.lit_slices;
  }
  stats_.voxelize = density_plan_.stats;
}

void FroxelFog::decide_regime(const ShadowMap& shadow, const ShadowMap* previous) {
  const bool use_history = profile_.reprojection && have_history_ && view_history_valid_;
  // The previous map matters only to history, and only when the sun itself
  // moved (a camera move re-fits the map around the same light).
  light_changed_ = use_history && profile_.light_change_rejection && previous && previous->size > 0 &&
                   shadow.size > 0 && previous->direction_to_sun != shadow.direction_to_sun;
  // Whether the history saw another sun (whatever rejection is set to): no
  // still view then. Without a shadow map the visibility is 1 for any sun.
  const glm::vec3 sun = shadow.size > 0 ? shadow.direction_to_sun : glm::vec3(0.0f);
  const bool sun_moved = sun != history_sun_;
  history_sun_ = sun;
  // A still view: the history was lit by the same camera and sun, over the
  // same lit and active froxels (static geometry), so its samples differ
  // from this frame's only by the jitter.
  const bool still = use_history && !sun_moved && same_view(view_, history_view_) &&
                     view_.lit_slices == history_view_.lit_slices &&
                     view_.active_slices == history_view_.active_slices;
  // A still view's samples repeat with the jitter sequence: once each phase
  // is in (add_still_sample), their mean is the converged lighting and stands
  // in for it; reprojection then only fades the history towards it.
  const bool accumulating = still && profile_.still_accumulation && lighting_samples_ == 1 && density_kept_;
  if (!accumulating) still_phases_ = 0;
  if (!use_history) {
    regime_ = FogRegime::NoHistory;
  } else if (!still) {
    regime_ = FogRegime::Moving;
  } else if (!accumulating) {
    regime_ = FogRegime::Still;
  } else if (still_phases_ != kAllPhases) {
    regime_ = FogRegime::StillAccumulating;
  } else {
    // Once what the history holds besides that mean is under 1/64 of it, a
    // frame changes nothing visible: the visibility (and the density it was
    // lit with) is kept as it is.
    regime_ = fading_share_ < kFreezeShare ? FogRegime::Frozen : FogRegime::StillMean;
  }
  // In a still view the jitter sequence repeats every kJitterFrames; the
  // reprojection's running mean counts the still frames.
  still_frames_ = still ? std::min(still_frames_ + 1, kMaxStillFrames) : 0;
  // The filter trades bias for less noise and ghosting in motion; a still
  // view with a whole jitter sequence accumulated needs neither.
  const bool converged = profile_.still_accumulation && still_frames_ >= kJitterFrames;
  filter_now_ = profile_.filter && !converged;
  stats_.history_used = use_history;
  stats_.light_changed = light_changed_;
  stats_.still_frames = still_frames_;
  stats_.filtered = filter_now_;
  stats_.jitter_complete = regime_ == FogRegime::StillMean || regime_ == FogRegime::Frozen;
  stats_.lighting_frozen = regime_ == FogRegime::Frozen;
}

void FroxelFog::lighting(const ShadowMap& shadow, JobSystem& jobs, const ShadowMap* previous) {
  decide_regime(shadow, previous);
  switch (regime_) {
    case FogRegime::Frozen:
      return;  // last frame's visibility stands
    case FogRegime::StillMean:
      volume_stale_ = true;
      blended_ = -1;  // reprojection blends the still mean, not a lighting
      return;
    case FogRegime::NoHistory:
    case FogRegime::Moving:
    case FogRegime::Still:
    case FogRegime::StillAccumulating:
      break;
  }
  if (fixed_point())
    light_in<Q15SunTerm>(fixed_, shadow, jobs, previous);
  else
    light_in<FloatSunTerm>(float_, shadow, jobs, previous);
}

template <class F>
void FroxelFog::light_in(SunBuffers<typename F::Value>& b, const ShadowMap& shadow, JobSystem& jobs,
                         const ShadowMap* previous) {
  using Value = typename F::Value;
  volume_stale_ = true;
  const bool accumulating = regime_ == FogRegime::StillAccumulating;
  JitterInputs jitter;
  jitter.enabled = profile_.jitter;
  jitter.frame = frame_;
  jitter.samples = lighting_samples_;
  const VolumeShadow volume_shadow(shadow, view_.camera.position);
  const VolumeShadow previous_shadow = light_changed_ ? VolumeShadow(*previous, view_.camera.position) : VolumeShadow();
  // Each job voxelises its rows right before lighting them (in cache).
  const std::function<void(int, int)> voxelize = [this](int y0, int y1) {
    voxelize_rows(view_, medium_, density_plan_, y0, y1, density_);
  };
  // A kept density is read from memory instead: requested ahead, row by row.
  const std::function<void(int, int)> prefetch = [this](int y0, int y1) {
    const FroxelGrid& g = view_.grid;
    const char* begin = reinterpret_cast<const char*>(density_.data() + g.index(0, y0, 0));
    const char* end = reinterpret_cast<const char*>(density_.data() + g.index(0, y1, 0));
    for (const char* p = begin; p < end; p += 64) __builtin_prefetch(p);
  };
  // With still_settled, a still view lights again only the froxels whose
  // history is not settled (settled_froxels.h), once the history holds two
  // samples (this run's first and the frame before it): with one, a still
  // view of fog_volumes missed edges that the second sample showed.
  const bool settle = accumulating && profile_.still_settled && still_phases_ != 0;
  SettledSamples<Value> settled;
  if (settle) {
    unsettled_spans(view_, b.history[1 - current_], jobs, settled_scratch_, unsettled_);
    settled.spans = &unsettled_;
    settled.values = &b.history[1 - current_];
    for (const SliceSpan& s : unsettled_) stats_.unsettled_froxels += size_t(s.end - s.first);
  }
  light_froxels(view_, density_, volume_shadow, jitter, jobs, b.current, density_kept_ ? prefetch : voxelize,
                light_changed_ ? &previous_shadow : nullptr, light_changed_ ? &b.light_change : nullptr,
                settle ? &settled : nullptr);
  density_valid_ = true;
  blended_ = -1;
  if (accumulating) add_still_sample(b, jobs);
}

template <class Value>
void FroxelFog::add_still_sample(SunBuffers<Value>& b, JobSystem& jobs) {
  // Without jitter every frame takes the same sample: one is the mean.
  const unsigned phase = profile_.jitter ? 1u << (((frame_ % kJitterFrames) + kJitterFrames) % kJitterFrames)
                                         : kAllPhases;
  if (still_phases_ & phase) return;
  const bool first = still_phases_ == 0;
  still_samples_ = first ? 1 : still_samples_ + 1;
  still_phases_ |= phase;
  fading_share_ = 1.0f;  // at most all of the history differs from the mean when it completes
  const bool complete = still_phases_ == kAllPhases;
  const FroxelGrid& g = view_.grid;
  b.still_mean.resize(g.count());
  if constexpr (std::is_same_v<Value, float>) {
    const float scale = complete ? 1.0f / float(still_samples_) : 1.0f;
    jobs.parallel_for("fog.still_mean", g.columns(), 64, [&](size_t begin, size_t end) {
      for (size_t c = begin; c < end; ++c) {
        float* sum = b.still_mean.data() + c * g.nz();
        const float* sample = b.current.data() + c * g.nz();
        for (int k = 0; k < view_.lit_slices[c]; ++k) sum[k] = ((first ? 0.0f : sum[k]) + sample[k]) * scale;
      }
    });
  } else {
    // Codes are summed exactly; the mean rounds half up, and a mean of codes
    // is a code (at most 32767).
    still_sum_.resize(g.count());
    const uint32_t samples = uint32_t(still_samples_);
    jobs.parallel_for("fog.still_mean", g.columns(), 64, [&](size_t begin, size_t end) {
      for (size_t c = begin; c < end; ++c) {
        uint32_t* sum = still_sum_.data() + c * g.nz();
        const uint16_t* sample = b.current.data() + c * g.nz();
        uint16_t* mean = b.still_mean.data() + c * g.nz();
        for (int k = 0; k < view_.lit_slices[c]; ++k) {
          sum[k] = (first ? 0u : sum[k]) + sample[k];
          if (complete) mean[k] = uint16_t((sum[k] + samples / 2) / samples);
        }
      }
    });
  }
}

void FroxelFog::reproject(JobSystem& jobs) {
  if (!profile_.reprojection || regime_ == FogRegime::Frozen) return;
  if (fixed_point())
    reproject_in<Q15SunTerm>(fixed_, jobs);
  else
    reproject_in<FloatSunTerm>(float_, jobs);
}

template <class F>
void FroxelFog::reproject_in(SunBuffers<typename F::Value>& b, JobSystem& jobs) {
  float weight = profile_.history_weight;
  bool clamp = profile_.history_clamp;
  switch (regime_) {
    case FogRegime::StillMean:
      // A constant target: the profile's weight fades the rest geometrically.
      fading_share_ *= weight;
      clamp = false;
      break;
    case FogRegime::Still:
    case FogRegime::StillAccumulating:
      // The jitter sequence repeats every kJitterFrames. A running mean
      // (weight s / (s + 1) once it exceeds the profile's) averages it evenly
      // and converges to the many-sample result, where a fixed weight keeps
      // cycling around it; nothing moves, so there is no ghost to clamp.
      if (profile_.still_accumulation) {
        weight = std::max(weight, float(still_frames_) / float(still_frames_ + 1));
        clamp = false;
      }
      break;
    case FogRegime::NoHistory:
    case FogRegime::Moving:
    case FogRegime::Frozen:
      break;
  }
  auto& out = b.history[current_];
  if (regime_ != FogRegime::NoHistory) {
    const auto& current = regime_ == FogRegime::StillMean ? b.still_mean : b.current;
    stats_.reproject = reproject_history(view_, current, history_view_, b.history[1 - current_], weight, clamp,
                                         jobs, out, light_changed_ ? &b.light_change : nullptr);
  } else {
    out.swap(b.current);  // no history: the blend is the current light (lighting rewrites current)
  }
  blended_ = current_;
  history_view_ = view_;
  have_history_ = true;
  current_ = 1 - current_;
}

void FroxelFog::filter(JobSystem& jobs) {
  if (!filter_now_) return;
  if (fixed_point())
    filter_slices(view_, blended(fixed_), jobs, fixed_.scratch, fixed_.filtered);
  else
    filter_slices(view_, blended(float_), jobs, float_.scratch, float_.filtered);
}

MediumLighting medium_lighting(const FogSceneSettings& scene, const LightEnvironment& light, const Camera& camera) {
  MediumLighting m;
  m.phase = scene.phase;
  m.anisotropy = scene.anisotropy;
  m.sun_direction = light.sun_direction;
  m.sun_illuminance = light.sun_illuminance;
  m.light = &light;
  m.camera_position = camera.position;
  m.ambient_sh = light.ambient_sh;
  return m;
}

void FroxelFog::integrate(const LightEnvironment& light, JobSystem& jobs) {
  const MediumLighting m = medium_lighting(scene_, light, view_.camera);
  std::vector<glm::vec3> knots = sun_knots(view_, m, jobs);
  const bool same_light = same_medium_lighting(m, integrated_light_) && knots == integrated_knots_;
  // Nothing the integration reads has changed (a frozen view's density and
  // visibility, the same light): last frame's volume is this frame's, bit for bit.
  stats_.volume_kept = regime_ == FogRegime::Frozen && !volume_stale_ && same_light;
  if (stats_.volume_kept) return;
  stats_.integrated_froxels = fixed_point() ? integrate_in(fixed_, m, knots, same_light, jobs, fixed_volume_)
                                             : integrate_in(float_, m, knots, same_light, jobs, volume_);
  visibility_saved_ = is_still(regime_);
  integrated_light_ = m;
  integrated_light_.light = nullptr;  // borrowed for this frame only
  integrated_knots_ = std::move(knots);
  volume_stale_ = false;
}

template <class Value, class Froxel>
size_t FroxelFog::integrate_in(SunBuffers<Value>& b, const MediumLighting& m, const std::vector<glm::vec3>& knots,
                               bool same_light, JobSystem& jobs, std::vector<Froxel>& volume) {
  // A still view saves the visibility it integrates. The next frame, if it
  // is still too, has the same view, lit and active froxels and density (the
  // volume was integrated last frame, or kept since): under the same light
  // it integrates only what changed.
  IncrementalIntegration<Value> incremental;
  if (is_still(regime_)) {
    incremental.previous = &b.integrated_visibility;
    incremental.continue_volume = visibility_saved_ && density_kept_ && same_light;
  }
  return integrate_columns(view_, density_, integration_input(b), m, knots, jobs, volume, incremental);
}

void FroxelFog::composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) const {
  if (fixed_point())
    composite_fog(view_.grid, fixed_volume_, buffers.distance, buffers.color, buffers.width, x0, y0, x1, y1);
  else
    composite_fog(view_.grid, volume_, buffers.distance, buffers.color, buffers.width, x0, y0, x1, y1);
}

void FroxelFog::composite_fragments(std::span<EdgeFragment> fragments) const {
  if (fixed_point())
    composite_fog_fragments(view_.grid, fixed_volume_, fragments);
  else
    composite_fog_fragments(view_.grid, volume_, fragments);
}

void FroxelFog::render(const FrameView& view, const LightEnvironment& light, const ShadowMap& shadow,
                       JobSystem& jobs, const std::vector<float>* distance, const ShadowMap* previous_shadow) {
  begin_frame(view, jobs, distance);
  density();
  lighting(shadow, jobs, previous_shadow);
  reproject(jobs);
  filter(jobs);
  integrate(light, jobs);
}

}  // namespace cr

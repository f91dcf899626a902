// Temporal behaviour: a static view converges to the non-temporal many-sample
// result; a fast camera path stays within a stated ghosting bound; a camera
// cut drops the history.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>
#include <cstring>
#include <utility>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kTemporalW = 96, kTemporalH = 64;
const glm::vec3 kSun(0.8f, 0.35f, 0.2f);

FogProfileSettings profile(bool reprojection, bool clamp = true, bool light_change_rejection = true) {
  FogProfileSettings p;
  p.history_clamp = clamp;
  p.light_change_rejection = light_change_rejection;
  p.slices = 32;
  p.fog_distance = 48.0f;
  p.reprojection = reprojection;
  return p;
}

std::vector<float> sky_distances() { return std::vector<float>(size_t(kTemporalW) * kTemporalH, INFINITY); }

// The still views' camera, its shadow map and light.
struct StillView {
  Camera cam = camera_at({-6, 3, 20}, {2, 4, -10}, kTemporalW, kTemporalH);
  ShadowMap shadow = wall_shadow(cam, kSun);
  LightEnvironment light = cr::fog_test::light(kSun, 10000.0f, 50.0f);
};

// The composite of one frame with all seven jitter samples averaged and no history.
std::vector<glm::vec3> many_sample(const FrameView& view, const LightEnvironment& l, const ShadowMap& shadow,
                                   JobSystem& jobs, bool filter = true) {
  FogProfileSettings p = profile(false);
  p.filter = filter;
  FroxelFog fog(p, uniform_fog(0.04f, glm::vec3(0.9f)));
  fog.set_lighting_samples(7);
  FrameView v = view;
  v.frame = 0;
  v.history_valid = false;
  return composite(fog, v, l, shadow, jobs, sky_distances(), glm::vec3(0.0f));
}

// Froxels of the frame's volume (active slices) that differ, bit for bit,
// from integrating the frame's density and visibility afresh.
size_t volume_mismatches(const FroxelFog& fog, const LightEnvironment& l, JobSystem& jobs) {
  const FroxelView& view = fog.view();
  const MediumLighting m = medium_lighting(fog.scene(), l, view.camera);
  std::vector<IntegratedFroxel> fresh;
  integrate_columns(view, fog.density_volume(), fog.sun_visibility(), m, sun_knots(view, m, jobs), jobs, fresh);
  size_t mismatches = 0;
  for (size_t c = 0; c < view.grid.columns(); ++c)
    for (int k = 0; k < view.active_slices[c]; ++k) {
      const size_t i = c * size_t(view.grid.nz()) + size_t(k);
      mismatches += std::memcmp(&fresh[i], &fog.volume()[i], sizeof(IntegratedFroxel)) != 0;
    }
  return mismatches;
}

// Raises worst[i] to image i's mean error against the reference.
void raise_worst(const std::vector<glm::vec3>& reference, const std::array<const std::vector<glm::vec3>*, 3>& images,
                 std::array<double, 3>& worst) {
  for (size_t i = 0; i < images.size(); ++i) worst[i] = std::max(worst[i], mean_relative_error(reference, *images[i]));
}

}  // namespace

TEST_CASE("reprojection of a static view converges to the non-temporal many-sample result") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  double converged[2] = {0.0, 0.0};
  for (bool accumulate : {false, true}) {
    CAPTURE(accumulate);
    // The target: the seven samples averaged, no history; filtered unless
    // the still view's accumulation drops the filter.
    const bool filter = !accumulate;
    const std::vector<glm::vec3> reference =
        many_sample(frame_view(cam, cam, 0, false, kTemporalW, kTemporalH), l, shadow, jobs, filter);
    FogProfileSettings one = profile(false), temporal_profile = profile(true);
    one.filter = filter;
    temporal_profile.still_accumulation = accumulate;
    FroxelFog single(one, uniform_fog(0.04f, glm::vec3(0.9f)));
    const double single_error = mean_relative_error(
        reference, composite(single, frame_view(cam, cam, 3, false, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {}));
    FroxelFog temporal(temporal_profile, uniform_fog(0.04f, glm::vec3(0.9f)));
    double error = 0.0;
    for (int f = 0; f < 42; ++f) {
      const auto out =
          composite(temporal, frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {});
      error = mean_relative_error(reference, out);
      if (f > 0) CHECK((temporal.stats().reproject.identity || temporal.stats().lighting_frozen));
      CHECK(temporal.stats().still_frames == f);
      CHECK(temporal.stats().filtered == (!accumulate || f < kJitterFrames));
    }
    MESSAGE("static view, still accumulation " << accumulate << ": single-sample error " << single_error
                                               << ", temporal error after 42 frames " << error);
    CHECK(single_error > 0.002);        // the jitter matters in this scene (shaft edges)
    CHECK(error < 0.4 * single_error);  // the history averages the sequence
    CHECK(error < 0.01);
    converged[accumulate] = error;
  }
  // The running mean weighs the sequence evenly; a fixed weight keeps cycling around the target.
  CHECK(converged[1] < 0.25 * converged[0]);
}

TEST_CASE("a converged still view keeps its lighting until the camera, the sun or the geometry moves") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  const Camera moved = camera_at({-6, 3, 20.01}, {2, 4, -10}, kTemporalW, kTemporalH);
  const std::vector<glm::vec3> reference =
      many_sample(frame_view(cam, cam, 0, false, kTemporalW, kTemporalH), l, shadow, jobs, /*filter=*/false);
  FroxelFog fog(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  std::vector<glm::vec3> last;
  // Frames 1-7 are still and lit, one jitter phase each; from frame 8 their
  // mean stands in for the lighting and the history fades towards it by the
  // profile's weight (6/7) until the rest is under 1/64: frozen at frame 35.
  constexpr int kComplete = 1 + kJitterFrames, kFreeze = kComplete + 27;
  double error_complete = 0.0, error_before = 0.0;
  for (int f = 0; f <= kFreeze + 2; ++f) {
    const auto out = composite(fog, frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {});
    CHECK(fog.stats().jitter_complete == (f >= kComplete));
    CHECK(fog.stats().lighting_frozen == (f >= kFreeze));
    CHECK(fog.stats().volume_kept == (f >= kFreeze));  // the same light: no integration either
    if (f == kComplete) error_complete = mean_relative_error(reference, out);
    if (f == kFreeze - 1) error_before = mean_relative_error(reference, out);
    if (f >= kFreeze) CHECK(out == last);  // nothing recomputed, nothing changes
    last = out;
  }
  MESSAGE("still view error against the seven-sample result: " << error_complete << " when the jitter sequence is "
                                                                   "complete, "
                                                                << error_before << " when it freezes");
  CHECK(error_before < 0.25 * error_complete);  // the history fades towards the mean
  CHECK(error_before < 0.0005);
  // Other light on the frozen visibility (a brighter sun, then sun_at, then
  // sun_at giving other values): integrated again, and the frame changes.
  const LightEnvironment brighter = light(kSun, 12000.0f, 50.0f);
  LightEnvironment hazy = l, hazier = l;
  hazy.sun_at = [](const glm::vec3*, glm::vec3* out, size_t n) { std::fill(out, out + n, glm::vec3(9000.0f)); };
  hazier.sun_at = [](const glm::vec3*, glm::vec3* out, size_t n) { std::fill(out, out + n, glm::vec3(8000.0f)); };
  int f = kFreeze + 3;
  for (const LightEnvironment* other : {&brighter, &std::as_const(hazy), &std::as_const(hazier)}) {
    const auto out = composite(fog, frame_view(cam, cam, f++, true, kTemporalW, kTemporalH), *other, shadow, jobs, sky_distances(), {});
    CHECK(fog.stats().lighting_frozen);
    CHECK_FALSE(fog.stats().volume_kept);
    CHECK(out != last);
    last = out;
  }
  // Geometry that moved in front of the still camera changes which froxels
  // are lit: not a still view.
  std::vector<float> wall = sky_distances();
  std::fill(wall.begin(), wall.begin() + wall.size() / 2, 6.0f);
  composite(fog, frame_view(cam, cam, f++, true, kTemporalW, kTemporalH), l, shadow, jobs, wall, {});
  CHECK_FALSE(fog.stats().lighting_frozen);
  CHECK(fog.stats().still_frames == 0);
  // A camera move (1 cm) or a sun move thaws it.
  composite(fog, frame_view(moved, cam, f++, true, kTemporalW, kTemporalH), l, wall_shadow(moved, kSun), jobs,
            sky_distances(), {});
  CHECK_FALSE(fog.stats().lighting_frozen);
  CHECK(fog.stats().still_frames == 0);
  for (int still = 0; still <= kFreeze; ++still)
    composite(fog, frame_view(moved, moved, f++, true, kTemporalW, kTemporalH), l, wall_shadow(moved, kSun), jobs, sky_distances(), {});
  CHECK(fog.stats().lighting_frozen);
  const glm::vec3 sun2 = glm::normalize(kSun + glm::vec3(0.0f, 0.01f, 0.0f));
  composite(fog, frame_view(moved, moved, f++, true, kTemporalW, kTemporalH), light(sun2, 10000.0f, 50.0f),
            wall_shadow(moved, sun2), jobs, sky_distances(), {});
  CHECK_FALSE(fog.stats().lighting_frozen);
}

TEST_CASE("without jitter a still view's one sample is its converged lighting, bit for bit") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  FogProfileSettings still = profile(true), single = profile(false);
  for (FogProfileSettings* p : {&still, &single}) {
    p->jitter = false;
    p->filter = false;
  }
  FroxelFog one(single, uniform_fog(0.04f, glm::vec3(0.9f)));
  const auto expected = composite(one, frame_view(cam, cam, 0, false, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {});
  FroxelFog fog(still, uniform_fog(0.04f, glm::vec3(0.9f)));
  for (int f = 0; f < 12; ++f) {
    const auto out = composite(fog, frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {});
    CHECK(fog.stats().jitter_complete == (f >= 2));  // the first still frame's sample covers every phase
    CHECK(out == expected);
  }
}

TEST_CASE("a still view voxelises its density once; the kept density is a fresh voxelisation's bits") {
  JobSystem jobs(2);
  const FogSceneSettings scene = noisy_volume_fog();
  const Camera cam = camera_at({-3, 2, 10}, {0, 2, -10}, kTemporalW, kTemporalH);
  const Camera moved = camera_at({-3, 2, 10.01}, {0, 2, -10}, kTemporalW, kTemporalH);
  const ShadowMap shadow = wall_shadow(cam, kSun);
  const LightEnvironment l = light(kSun, 10000.0f, 50.0f);
  std::vector<float> distance(size_t(kTemporalW) * kTemporalH);
  for (size_t i = 0; i < distance.size(); ++i) distance[i] = i % 3 == 0 ? INFINITY : 2.0f + float(i % 50);
  FroxelFog fog(profile(true), scene);
  for (int f = 0; f < 4; ++f) {
    composite(fog, frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH), l, shadow, jobs, distance, {});
    CHECK(fog.stats().density_kept == (f > 0));
  }
  // A fresh voxelisation of the same view.
  FroxelFog fresh(profile(false), scene);
  composite(fresh, frame_view(cam, cam, 3, false, kTemporalW, kTemporalH), l, shadow, jobs, distance, {});
  const FroxelGrid& g = fog.grid();
  size_t compared = 0, differing = 0;
  for (size_t c = 0; c < g.columns(); ++c)
    for (int k = 0; k < fog.view().lit_slices[c]; ++k, ++compared)
      differing += std::memcmp(&fog.density_volume()[c * g.nz() + size_t(k)],
                               &fresh.density_volume()[c * g.nz() + size_t(k)], sizeof(FogDensity)) != 0;
  CHECK(compared > g.count() / 4);
  CHECK(differing == 0);
  // A camera move, or geometry that changes the lit froxels, voxelises again.
  composite(fog, frame_view(moved, cam, 4, true, kTemporalW, kTemporalH), l, shadow, jobs, distance, {});
  CHECK_FALSE(fog.stats().density_kept);
  composite(fog, frame_view(moved, moved, 5, true, kTemporalW, kTemporalH), l, shadow, jobs, distance, {});
  CHECK(fog.stats().density_kept);
  std::vector<float> nearer = distance;
  for (size_t i = 0; i < nearer.size() / 2; ++i) nearer[i] = 3.0f;
  composite(fog, frame_view(moved, moved, 6, true, kTemporalW, kTemporalH), l, shadow, jobs, nearer, {});
  CHECK_FALSE(fog.stats().density_kept);
}

TEST_CASE("a still view integrates only the slices whose visibility changed, with the bits of integrating all") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  FroxelFog fog(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  size_t mismatched = 0, incremental_frames = 0;
  for (int f = 0; f < 40; ++f) {
    composite(fog, frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH), l, shadow, jobs, sky_distances(), {});
    mismatched += volume_mismatches(fog, l, jobs);
    const FroxelFogStats& s = fog.stats();
    // Frame 0 has no history and frame 1 no integration of this view to
    // continue: both integrate everything; frozen frames keep the volume.
    if (f <= 1) CHECK(s.integrated_froxels == s.active_froxels);
    if (f >= 2 && !s.volume_kept) {
      CHECK(s.integrated_froxels < s.active_froxels / 2);
      ++incremental_frames;
    }
  }
  CHECK(mismatched == 0);
  CHECK(incremental_frames >= 30);  // frames 2 to the freeze at 35
}

TEST_CASE("with still_settled, a still view lights only its unsettled froxels, and converges as when it lights all") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  FogProfileSettings settled_profile = profile(true);
  settled_profile.still_settled = true;
  FroxelFog settled(settled_profile, uniform_fog(0.04f, glm::vec3(0.9f)));
  FroxelFog exact(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  double worst = 0.0;
  for (int f = 0; f < 12; ++f) {
    CAPTURE(f);
    const FrameView view = frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH);
    const auto a = composite(settled, view, l, shadow, jobs, sky_distances(), {});
    const auto b = composite(exact, view, l, shadow, jobs, sky_distances(), {});
    worst = std::max(worst, mean_relative_error(b, a));
    const FroxelFogStats& s = settled.stats();
    CHECK(exact.stats().unsettled_froxels == 0);
    // Settling needs two samples in the history (frames 2 on) and stops with
    // the lighting once the jitter sequence is in (frame 8).
    if (f < 2 || f >= 8) CHECK(s.unsettled_froxels == 0);
    if (f >= 2 && f < 8) {
      CHECK(s.unsettled_froxels > 0);
      CHECK(s.unsettled_froxels < s.lit_froxels / 4);
    }
  }
  MESSAGE("still_settled against lighting every froxel, worst mean error over 12 frames: " << worst);
  CHECK(worst < 1e-4);
}

TEST_CASE("a still view integrates everything again under another light or after another view") {
  JobSystem jobs(2);
  const auto [home, shadow, l] = StillView{};
  const LightEnvironment brighter = light(kSun, 20000.0f, 50.0f);
  const Camera away = camera_at({-5, 3, 19}, {2, 4, -10}, kTemporalW, kTemporalH);
  const ShadowMap away_shadow = wall_shadow(away, kSun);
  FroxelFog fog(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  // Frames 0-3 at home, 4 under a brighter sun, 5 away, 6-8 home again.
  Camera prev = home;
  for (int f = 0; f < 9; ++f) {
    const Camera& cam = f == 5 ? away : home;
    composite(fog, frame_view(cam, prev, f, f > 0, kTemporalW, kTemporalH), f == 4 ? brighter : l, f == 5 ? away_shadow : shadow, jobs,
              sky_distances(), {});
    prev = cam;
    const FroxelFogStats& s = fog.stats();
    CAPTURE(f);
    // Incremental from the second still frame on; the light's change (4), the
    // move (5), the first frame back (6, not still) and the first still one
    // after it (7: the frame before did not keep its visibility) integrate
    // everything.
    if (f == 2 || f == 3 || f == 8) CHECK(s.integrated_froxels < s.active_froxels / 2);
    if (f >= 4 && f <= 7) CHECK(s.integrated_froxels == s.active_froxels);
  }
}

TEST_CASE("whatever came before, a still view settles on the same frame") {
  JobSystem jobs(2);
  const auto [home, home_shadow, l] = StillView{};
  constexpr int kSettle = 40;  // frozen by then (the jitter sequence, then 27 frames of fading)
  FroxelFog fresh(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  std::vector<glm::vec3> settled;
  for (int f = 0; f < kSettle; ++f)
    settled = composite(fresh, frame_view(home, home, f, f > 0, kTemporalW, kTemporalH), l, home_shadow, jobs, sky_distances(), {});
  REQUIRE(fresh.stats().lighting_frozen);
  const std::vector<float> sky = sky_distances();
  std::vector<float> wall = sky;
  std::fill(wall.begin(), wall.begin() + wall.size() / 3, 5.0f);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    CAPTURE(seed);
    // Random events (moves, other suns, light, geometry, history resets,
    // supersampled frames), each held for 1-12 frames, so that some become
    // still runs of their own; then the still view again.
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> event(0, 5), length(1, 12), side(0, 1);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const glm::vec3 other_suns[2] = {glm::normalize(kSun + glm::vec3(0.3f, 0.1f, 0.0f)),
                                     glm::normalize(kSun + glm::vec3(-0.3f, -0.1f, 0.1f))};
    FroxelFog fog(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
    Camera prev = home;
    int f = 0;
    size_t volume_mismatched = 0;  // against integrating each frame afresh (incremental integration)
    for (int e = 0; e < 12; ++e) {
      Camera cam = home;
      glm::vec3 sun = kSun;
      LightEnvironment lit = l;
      const std::vector<float>* distance = &sky;
      const int kind = event(rng);
      fog.set_lighting_samples(kind == 5 ? 3 : 1);
      if (kind == 0) cam = camera_at({-6 + 4 * unit(rng), 3 + unit(rng), 20 + 4 * unit(rng)}, {2, 4, -10}, kTemporalW, kTemporalH);
      if (kind == 1) sun = other_suns[side(rng)];
      if (kind == 1) lit = light(sun, 10000.0f, 50.0f);
      if (kind == 2) distance = &wall;
      if (kind == 3) lit = light(kSun, 10000.0f * float(1.5 + unit(rng)), 50.0f);
      const ShadowMap shadow = wall_shadow(cam, sun);
      for (int n = length(rng); n > 0; --n, ++f) {
        if (kind == 4 && n % 3 == 0) fog.reset_history();
        const auto out = composite(fog, frame_view(cam, prev, f, true, kTemporalW, kTemporalH), lit, shadow, jobs, *distance, {});
        for (const glm::vec3& c : out) REQUIRE(std::isfinite(c.x + c.y + c.z));
        volume_mismatched += volume_mismatches(fog, lit, jobs);
        prev = cam;
      }
    }
    fog.set_lighting_samples(1);
    std::vector<glm::vec3> out;
    for (int i = 0; i < kSettle; ++i, ++f) {
      out = composite(fog, frame_view(home, prev, f, true, kTemporalW, kTemporalH), l, home_shadow, jobs, sky_distances(), {});
      volume_mismatched += volume_mismatches(fog, l, jobs);
      prev = home;
    }
    CHECK(fog.stats().lighting_frozen);
    CHECK(volume_mismatched == 0);
    const double difference = mean_relative_error(settled, out);
    MESSAGE("seed " << seed << ": settled frame against a fresh start's: " << difference);
    CHECK(difference < 0.002);
  }
}

TEST_CASE("a fast camera path stays within the ghosting bound") {
  JobSystem jobs(2);
  const LightEnvironment l = light(kSun, 10000.0f, 50.0f);
  FroxelFog clamped(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  FroxelFog unclamped(profile(true, false), uniform_fog(0.04f, glm::vec3(0.9f)));
  Camera prev;
  std::array<double, 3> worst{};  // clamped, unclamped (HDRP), single sample
  for (int f = 0; f < 16; ++f) {
    // 1.5 m and 3 degrees of yaw per frame (90 m/s, 180 deg/s at 60 Hz).
    const double angle = glm::radians(3.0 * f);
    const glm::dvec3 pos(-10.0 + 1.5 * f, 3.0, 20.0);
    const Camera cam = camera_at(pos, pos + glm::dvec3(std::sin(angle), 0.05, -std::cos(angle)), kTemporalW, kTemporalH);
    const ShadowMap shadow = wall_shadow(cam, kSun);
    const FrameView view = frame_view(cam, f == 0 ? cam : prev, f, f > 0, kTemporalW, kTemporalH);
    const auto out = composite(clamped, view, l, shadow, jobs, sky_distances(), {});
    const auto out_unclamped = composite(unclamped, view, l, shadow, jobs, sky_distances(), {});
    const auto reference = many_sample(view, l, shadow, jobs);
    FroxelFog single(profile(false), uniform_fog(0.04f, glm::vec3(0.9f)));
    const auto single_out = composite(single, view, l, shadow, jobs, sky_distances(), {});
    if (f >= 7) raise_worst(reference, {&out, &out_unclamped, &single_out}, worst);
    prev = cam;
  }
  MESSAGE("fast path, worst mean error vs converged: clamped history " << worst[0] << ", unclamped (HDRP) "
                                                                       << worst[1] << ", single sample " << worst[2]);
  // Stated bound: with the clamped history, ghosting plus residual noise stays
  // below 4.5% mean relative luminance error and below the single-sample error.
  CHECK(worst[0] < 0.045);
  CHECK(worst[0] < worst[2]);
}

TEST_CASE("a moving light shaft ghosts within the bound") {
  JobSystem jobs(2);
  const Camera cam = camera_at({-6, 3, 20}, {2, 4, -10}, kTemporalW, kTemporalH);
  const FogSceneSettings medium = uniform_fog(0.04f, glm::vec3(0.9f));
  FroxelFog fog(profile(true), medium), blind(profile(true, true, false), medium), single(profile(false), medium);
  ShadowMap previous;
  std::array<double, 3> worst{};  // light-change rejection, light-blind, single sample
  bool measured = true;
  for (int f = 0; f < 16; ++f) {
    // The sun swings 2 degrees per frame: the wall's shadow sweeps through the fog.
    const float a = glm::radians(20.0f + 2.0f * float(f));
    const glm::vec3 sun(std::cos(a), 0.35f, std::sin(a));
    const ShadowMap shadow = wall_shadow(cam, sun);
    const LightEnvironment l = light(sun, 10000.0f, 50.0f);
    const FrameView view = frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH);
    const auto out = composite(fog, view, l, shadow, jobs, sky_distances(), {}, true, &previous);
    const auto out_blind = composite(blind, view, l, shadow, jobs, sky_distances(), {}, true, &previous);
    const auto out_single = composite(single, view, l, shadow, jobs, sky_distances(), {}, true, &previous);
    measured &= fog.stats().light_changed == (f > 0) && !blind.stats().light_changed;
    if (f >= 7) raise_worst(many_sample(view, l, shadow, jobs), {&out, &out_blind, &out_single}, worst);
    previous = shadow;
  }
  MESSAGE("moving shaft, worst mean error vs converged: light-change rejection " << worst[0] << ", light-blind "
                                                                                 << worst[1] << ", single sample "
                                                                                 << worst[2]);
  CHECK(measured);
  // Stated bound: with light-change rejection the moving shaft ghosts less
  // than the single sample's noise; blind to the light, history lags behind.
  CHECK(worst[0] < worst[2]);
  CHECK(worst[0] < 0.85 * worst[1]);
  CHECK(worst[0] < 0.035);
}

TEST_CASE("a previous shadow map under the same sun changes nothing") {
  JobSystem jobs(2);
  const auto [cam, shadow, l] = StillView{};
  ShadowMap refit = wall_shadow(cam, kSun, 30.0f);  // re-rendered, same light: the camera moved
  const FogSceneSettings medium = uniform_fog(0.04f, glm::vec3(0.9f));
  FroxelFog with(profile(true), medium), without(profile(true), medium);
  for (int f = 0; f < 4; ++f) {
    const FrameView view = frame_view(cam, cam, f, f > 0, kTemporalW, kTemporalH);
    const auto a = composite(with, view, l, shadow, jobs, sky_distances(), {}, true, &refit);
    const auto b = composite(without, view, l, shadow, jobs, sky_distances(), {});
    CHECK_FALSE(with.stats().light_changed);
    CHECK(a == b);
  }
}

TEST_CASE("a camera cut drops the history") {
  JobSystem jobs(1);
  const LightEnvironment l = light(kSun, 10000.0f, 50.0f);
  const Camera a = camera_at({-6, 3, 20}, {2, 4, -10}, kTemporalW, kTemporalH);
  const Camera b = camera_at({30, 3, -20}, {0, 4, 0}, kTemporalW, kTemporalH);
  FroxelFog fog(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  for (int f = 0; f < 5; ++f) composite(fog, frame_view(a, a, f, f > 0, kTemporalW, kTemporalH), l, wall_shadow(a, kSun), jobs, sky_distances(), {});
  CHECK(fog.stats().history_used);
  const ShadowMap sb = wall_shadow(b, kSun);
  const auto cut = composite(fog, frame_view(b, b, 5, false, kTemporalW, kTemporalH), l, sb, jobs, sky_distances(), {});
  CHECK_FALSE(fog.stats().history_used);
  FroxelFog fresh(profile(true), uniform_fog(0.04f, glm::vec3(0.9f)));
  const auto first = composite(fresh, frame_view(b, b, 5, false, kTemporalW, kTemporalH), l, sb, jobs, sky_distances(), {});
  CHECK(cut == first);  // nothing of the old view survives the cut
}

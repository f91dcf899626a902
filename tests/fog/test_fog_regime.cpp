// The fog's regime: one per frame, decided before lighting, in the order a
// still view goes through, and agreeing with the stats the report shows.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

constexpr int kRegimeW = 64, kRegimeH = 48;
const glm::vec3 kRegimeSun(0.8f, 0.35f, 0.2f);

FogProfileSettings small_profile(bool still_accumulation = true) {
  FogProfileSettings p;
  p.slices = 24;
  p.fog_distance = 48.0f;
  p.still_accumulation = still_accumulation;
  return p;
}

// Renders one frame of `fog` from `cam` (the last frame's camera `prev`).
void frame(FroxelFog& fog, const Camera& cam, const Camera& prev, int f, JobSystem& jobs) {
  composite(fog, frame_view(cam, prev, f, f > 0, kRegimeW, kRegimeH), light(kRegimeSun, 10000.0f, 50.0f), wall_shadow(cam, kRegimeSun), jobs,
            std::vector<float>(size_t(kRegimeW) * kRegimeH, INFINITY), glm::vec3(0.0f));
}

void check_stats_agree(const FroxelFog& fog) {
  const FroxelFogStats& s = fog.stats();
  const FogRegime r = fog.regime();
  CHECK(s.history_used == (r != FogRegime::NoHistory));
  CHECK(s.jitter_complete == (r == FogRegime::StillMean || r == FogRegime::Frozen));
  CHECK(s.lighting_frozen == (r == FogRegime::Frozen));
  CHECK((s.still_frames > 0) == is_still(r));
}

}  // namespace

TEST_CASE("a still view goes through the regimes in order; a move, a cut or no accumulation leave them") {
  JobSystem jobs(2);
  const Camera cam = camera_at({-6, 3, 20}, {2, 4, -10}, kRegimeW, kRegimeH);
  const Camera moved = camera_at({-6, 3, 20.5}, {2, 4, -10}, kRegimeW, kRegimeH);
  FroxelFog fog(small_profile(), uniform_fog(0.04f, glm::vec3(0.9f)));
  // Frame 0 has no history; frames 1-7 collect the seven jitter phases; from
  // frame 8 their mean stands in; at frame 35 the rest is under 1/64: frozen.
  for (int f = 0; f <= 36; ++f) {
    frame(fog, cam, cam, f, jobs);
    const FogRegime expected = f == 0   ? FogRegime::NoHistory
                               : f < 8  ? FogRegime::StillAccumulating
                               : f < 35 ? FogRegime::StillMean
                                        : FogRegime::Frozen;
    CAPTURE(f);
    CHECK(fog.regime() == expected);
    check_stats_agree(fog);
  }
  frame(fog, moved, cam, 37, jobs);
  CHECK(fog.regime() == FogRegime::Moving);
  check_stats_agree(fog);
  fog.reset_history();
  frame(fog, moved, moved, 38, jobs);
  CHECK(fog.regime() == FogRegime::NoHistory);
  check_stats_agree(fog);

  FroxelFog plain(small_profile(/*still_accumulation=*/false), uniform_fog(0.04f, glm::vec3(0.9f)));
  for (int f = 0; f < 12; ++f) {
    frame(plain, cam, cam, f, jobs);
    CHECK(plain.regime() == (f == 0 ? FogRegime::NoHistory : FogRegime::Still));
    check_stats_agree(plain);
  }
}

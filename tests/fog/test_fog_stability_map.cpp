// The fog's stability map (fog/tools/fog_stability.h) at its extremes: no NaN
// or Inf in any frame's volume, image or reference, and history rejection
// engaging under a fast camera while staying near 0 for a still one.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "fog/tools/fog_stability.h"

using namespace cr;

namespace {

FogStabilityOptions small(bool reference) {
  FogStabilityOptions o;
  o.width = 64;
  o.height = 40;
  o.reference = reference;
  o.samples = 16;
  return o;
}

}  // namespace

TEST_CASE("fog stability map: no non-finite value at the extremes of extinction, anisotropy and speed") {
  JobSystem jobs(2);
  for (const float extinction : {1e3f, 1e-30f})  // mean free paths 1 mm and 1e30 m, the scene's limits
    for (const float g : {-0.99f, 0.99f})
      for (const float speed : {0.0f, 10.0f}) {
        FogStabilityCase c;
        c.extinction = extinction;
        c.anisotropy = g;
        c.speed = speed;
        c.frames = 4;
        const FogStabilityCell cell = evaluate_fog_stability(c, small(true), jobs);
        INFO("extinction " << extinction << ", g " << g << ", speed " << speed);
        CHECK(cell.non_finite == 0);
        CHECK(cell.non_finite_reference == 0);
        CHECK(std::isfinite(cell.error.mean));
      }
}

TEST_CASE("fog stability map: history rejection engages under a fast camera and stays low for a still one") {
  JobSystem jobs(2);
  auto rejection = [&](float speed, bool reprojection = true) {
    FogStabilityCase c;
    c.speed = speed;
    c.reprojection = reprojection;
    c.frames = 6;
    const FogStabilityCell cell = evaluate_fog_stability(c, small(false), jobs);
    MESSAGE("speed " << speed << " m/frame" << std::string(reprojection ? "" : ", no reprojection")
                     << ": rejected " << cell.history_rejected << ", clamped " << cell.history_clamped);
    CHECK(cell.non_finite == 0);
    return cell;
  };
  const FogStabilityCell still = rejection(0.0f), slow = rejection(0.1f), fast = rejection(3.0f);
  const FogStabilityCell off = rejection(3.0f, false);
  // Measured (64x40): still 0 / 0, 0.1 m/frame 0 / 0.0045, 3 m/frame 0.057 / 0.0083.
  CHECK(still.history_rejected == 0.0);
  CHECK(still.history_clamped == 0.0);
  CHECK(slow.history_rejected < 0.01);
  CHECK(fast.history_rejected > 0.02);
  CHECK(fast.history_rejected + fast.history_clamped > 5.0 * (slow.history_rejected + slow.history_clamped));
  CHECK(off.history_rejected == 0.0);  // no history, nothing to reject
  CHECK(off.history_clamped == 0.0);
}

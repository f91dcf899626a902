// The sky's stability map (atmosphere/tools/sky_stability.h) on coarse grids
// that include its extremes: no NaN or Inf anywhere, and each fallback
// engages where it should and nowhere else. The LUTs are the built-in
// (desktop-size, RGB) ones, as sky-stability evaluates them.
#include <doctest/doctest.h>

#include <cmath>

#include "atmosphere/tools/sky_stability.h"

using namespace cr;

namespace {

SkyStabilityOptions no_reference() {
  SkyStabilityOptions o;
  o.reference = false;
  return o;
}

}  // namespace

TEST_CASE("sky stability map: no non-finite value on a grid through the extremes") {
  JobSystem jobs(2);
  const AtmosphereSettings s;
  const AtmosphereModel earth;
  auto check = [&](const AtmosphereModel& m, double zenith, double altitude, const SkyStabilityOptions& o) {
    const SkyStabilityCell c = evaluate_sky_stability(m, s, zenith, altitude, o, jobs);
    INFO("sun zenith " << zenith << ", altitude " << altitude << " m, density x" << m.rayleigh_scattering.x / 5.802e-6f
                       << ", g " << m.mie_g << ": LUTs " << c.non_finite_luts << ", sky " << c.non_finite_sky
                       << ", geometry " << c.non_finite_geometry << ", reference " << c.non_finite_reference);
    CHECK(c.non_finite() == 0);
    if (o.reference) {
      CHECK(std::isfinite(c.score.mean));
      CHECK(std::isfinite(c.score.noise_mean));
    }
  };
  for (const double zenith : {0.0, 95.0, 180.0}) {
    for (const double altitude : {0.0, 1e3, 1e5, 1e6}) check(earth, zenith, altitude, no_reference());
    for (const float k : {0.01f, 100.0f}) check(with_density_scale(earth, k), zenith, 1.0, no_reference());
    for (const float g : {-0.99f, 0.99f}) {
      AtmosphereModel m = earth;
      m.mie_g = g;
      check(m, zenith, 1.0, no_reference());
    }
  }
  // The reference too, at the extremes (few paths: only finiteness is checked).
  SkyStabilityOptions tiny;
  tiny.width = 8;
  tiny.height = 4;
  tiny.spp = 4;
  check(earth, 180.0, 1e6, tiny);
  check(with_density_scale(earth, 100.0f), 0.0, 0.0, tiny);
}

TEST_CASE("sky stability map: the space fallback engages exactly above the fallback altitude") {
  JobSystem jobs(2);
  const AtmosphereSettings s;
  const AtmosphereModel earth;
  const double top = s.space_altitude;
  // 1 mm either side: the plan's altitude comes from the planet-centred camera position (double, ~1e-9 m).
  for (const double altitude : {0.0, 1e4, top - 1e-3, top, top + 1e-3, 1e6}) {
    const SkyStabilityCell c = evaluate_sky_stability(earth, s, 45.0, altitude, no_reference(), jobs);
    INFO("altitude " << altitude << " m");
    CHECK(c.space == (altitude > top));
    CHECK(c.non_finite() == 0);
  }
}

TEST_CASE("sky stability map: the series clamp and the orders' cap engage in dense, bright air, not for Earth") {
  JobSystem jobs(2);
  const AtmosphereSettings s;
  const AtmosphereModel earth;
  // Earth by day: f_ms far below max_fms, the explicit orders within their cap.
  for (const double zenith : {0.0, 45.0, 80.0}) {
    const SkyStabilityCell c = evaluate_sky_stability(earth, s, zenith, 1.0, no_reference(), jobs);
    CHECK(c.ms_clamped == 0);
    CHECK_FALSE(c.orders_capped);
    CHECK(c.max_fms < s.multiscattering_max_fms);
  }
  // Thin air: no clamp, no cap.
  const SkyStabilityCell thin = evaluate_sky_stability(with_density_scale(earth, 0.01f), s, 45.0, 1.0, no_reference(), jobs);
  CHECK(thin.ms_clamped == 0);
  CHECK_FALSE(thin.orders_capped);
  CHECK(thin.explicit_orders == s.multiscattering_explicit_orders);
  // Dense air (x100): light scatters again almost surely, f_ms passes max_fms and the series is clamped;
  // the explicit orders run to their cap without bringing the series' share under tail_share.
  const SkyStabilityCell dense = evaluate_sky_stability(with_density_scale(earth, 100.0f), s, 45.0, 1.0, no_reference(), jobs);
  MESSAGE("x100: " << dense.ms_clamped << " of " << dense.ms_texels << " texels clamped, largest f_ms "
                   << dense.max_fms << ", " << dense.explicit_orders << " explicit orders");
  // Measured: 384 of 2048 texels clamped, largest f_ms 0.99989.
  CHECK(dense.ms_clamped > dense.ms_texels / 10);
  CHECK(dense.max_fms > s.multiscattering_max_fms);
  CHECK(dense.orders_capped);
  CHECK(dense.explicit_orders == s.multiscattering_max_explicit_orders);
  // The clamp is per texel and does not depend on the sun or the camera (f_ms is the medium's).
  const SkyStabilityCell dense_night =
      evaluate_sky_stability(with_density_scale(earth, 100.0f), s, 180.0, 1e4, no_reference(), jobs);
  CHECK(dense_night.ms_clamped == dense.ms_clamped);
}

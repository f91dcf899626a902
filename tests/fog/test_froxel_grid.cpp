#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "engine/core/fast_math.h"
#include "fog/froxel_grid.h"
#include "fog/jitter_sequence.h"

using namespace cr;

TEST_CASE("log slice encoding round-trips and spans [near, far]") {
  for (float u : {0.0f, 0.25f, 0.75f, 1.0f}) {
    const FroxelGrid g(1280, 720, 8, 64, 0.1f, 64.0f, u);
    CHECK(g.nx() == 160);
    CHECK(g.ny() == 90);
    CHECK(g.boundary(0) == doctest::Approx(0.1f));
    CHECK(g.boundary(64) == doctest::Approx(64.1f));
    for (int k = 0; k < 64; ++k) {
      CHECK(g.thickness(k) > 0.0f);
      CHECK(g.center(k) > g.boundary(k));
      CHECK(g.center(k) < g.boundary(k + 1));
    }
    for (float d = 0.1f; d <= 64.1f; d *= 1.37f) {
      const float e = g.encode(d);
      CHECK(e >= 0.0f);
      CHECK(e <= 1.0f);
      CHECK(g.decode(e) == doctest::Approx(d).epsilon(1e-5));
    }
    for (int k = 0; k <= 64; ++k) CHECK(g.slice_coord(g.boundary(k)) == doctest::Approx(float(k)).epsilon(1e-4));
  }
}

TEST_CASE("slice uniformity: 1 is linear, 0 concentrates slices near the camera") {
  const FroxelGrid linear(64, 64, 8, 32, 0.5f, 32.0f, 1.0f);
  // c = 0.001 is linear to within 1.6% of a slice over 32 m.
  for (int k = 0; k < 32; ++k) CHECK(linear.thickness(k) == doctest::Approx(1.0f).epsilon(0.02));
  const FroxelGrid log(64, 64, 8, 32, 0.5f, 32.0f, 0.0f);
  CHECK(log.thickness(0) < 0.2f);
  CHECK(log.thickness(31) > 3.0f);
  // HDRP default 0.75 lies between.
  const FroxelGrid hdrp(64, 64, 8, 32, 0.5f, 32.0f, 0.75f);
  CHECK(hdrp.thickness(0) > log.thickness(0));
  CHECK(hdrp.thickness(0) < linear.thickness(0));
}

TEST_CASE("distances outside the grid clamp to its ends") {
  const FroxelGrid g(100, 50, 8, 16, 0.1f, 10.0f, 0.75f);
  CHECK(g.nx() == 13);
  CHECK(g.ny() == 7);
  CHECK(g.encode(0.0f) == 0.0f);
  CHECK(g.encode(1e9f) == 1.0f);
  CHECK(g.encode(INFINITY) == 1.0f);
}

TEST_CASE("the 7-frame jitter sequence: HDRP depth offsets and a hexagon inside the froxel") {
  const float expected[7] = {7, 3, 11, 5, 9, 1, 13};
  float sum_x = 0, sum_y = 0;
  for (int i = 0; i < 7; ++i) {
    const FroxelJitter j = froxel_jitter(i);
    CHECK(j.depth == doctest::Approx(expected[i] / 14.0f));
    CHECK(std::abs(j.lateral.x) < 0.5f);
    CHECK(std::abs(j.lateral.y) < 0.5f);
    sum_x += j.lateral.x;
    sum_y += j.lateral.y;
    CHECK(froxel_jitter(i + 7).depth == j.depth);
  }
  CHECK(std::abs(sum_x) < 1e-5f);  // centred pattern: no bias
  CHECK(std::abs(sum_y) < 1e-5f);
  for (int x = 0; x < 50; ++x) {
    const float h = column_hash(x, 3);
    CHECK(h >= 0.0f);
    CHECK(h < 1.0f);
  }
}

TEST_CASE("slice_of finds the slice whose boundaries bracket a distance") {
  for (float u : {0.0f, 0.75f, 1.0f}) {
    const FroxelGrid g(1280, 720, 8, 64, 0.1f, 128.0f, u);
    for (int k = 0; k < 64; ++k) {
      CHECK(g.slice_of(g.boundary(k)) == k);
      CHECK(g.slice_of(std::nextafter(g.boundary(k + 1), 0.0f)) == k);
    }
    for (float d = 0.1f; d < 128.1f; d = d * 1.013f + 1e-3f) {
      const int k = g.slice_of(d);
      CHECK(g.boundary(k) <= d);
      if (k < 63) CHECK(d < g.boundary(k + 1));
    }
    CHECK(g.slice_of(0.0f) == 0);
    CHECK(g.slice_of(INFINITY) == 63);
  }
}

TEST_CASE("slice_of equals a linear boundary search on dense sweeps, thin log slices included") {
  struct Case {
    int slices;
    float near, distance, uniformity;
  };
  for (const Case& c : {Case{64, 0.1f, 64.0f, 0.75f}, Case{64, 0.1f, 96.0f, 0.0f}, Case{1024, 0.05f, 5000.0f, 0.0f},
                        Case{7, 1.0f, 3.0f, 1.0f}, Case{256, 0.1f, 1e6f, 0.3f}}) {
    const FroxelGrid g(320, 180, 8, c.slices, c.near, c.distance, c.uniformity);
    int mismatches = 0;
    auto linear = [&](float d) {
      d = std::min(std::max(d, g.near_distance()), g.far_distance());
      int k = 0;
      while (k + 1 < g.nz() && d >= g.boundary(k + 1)) ++k;
      return k;
    };
    for (int k = 0; k <= g.nz(); ++k)
      for (float d : {g.boundary(k), std::nextafter(g.boundary(k), 0.0f), std::nextafter(g.boundary(k), INFINITY)})
        mismatches += g.slice_of(d) != linear(d);
    const float span = g.far_distance() - g.near_distance();
    for (int i = 0; i <= 200000; ++i) {
      const float d = g.near_distance() + span * float(i) / 200000.0f;
      mismatches += g.slice_of(d) != linear(d);
    }
    CHECK(mismatches == 0);
  }
}

TEST_CASE("fast_log matches log over the slice encoding's range, and log_c/log_scale give slice_coord") {
  // The encoding's argument 1 + c (d - near) lies in [1, 1 + 2 fog_distance]
  // (c <= 2); the reprojection takes slice coordinates from fast_log.
  double worst = 0.0;
  for (float x = 1.0f; x < 4096.0f; x = std::nextafter(x * 1.001f, 1e9f)) {
    const double exact = std::log(double(x));
    worst = std::max(worst, std::abs(double(fast_log(x)) - exact) / std::max(exact, 0.01));
  }
  CHECK(worst < 3e-7);
  CHECK(fast_log(1.0f) == 0.0f);
  const FroxelGrid g(1280, 720, 8, 64, 0.1f, 128.0f, 0.75f);
  for (float d = 0.1f; d <= 128.1f; d *= 1.21f)
    CHECK(fast_log(1.0f + g.log_c() * (d - g.near_distance())) * g.log_scale() ==
          doctest::Approx(g.slice_coord(d)).epsilon(1e-5));
}

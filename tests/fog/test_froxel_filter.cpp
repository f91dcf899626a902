// fog.filter against its kernel: a 3x3 Gaussian (sigma = 1 froxel) within a
// slice, normalised, with edge taps clamped to the grid.
#include <doctest/doctest.h>

#include <cmath>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

struct FilterCase {
  JobSystem jobs{2};
  Camera cam = camera_at({0, 2, 0}, {0, 2, -10}, 80, 48);
  FroxelGrid grid{80, 48, 8, 12, cam.znear, 64.0f, 0.5f};
  FroxelView view = make_froxel_view(grid, cam, jobs);
  std::vector<float> scratch, out;
  const std::vector<float>& filter(const std::vector<float>& in) {
    filter_slices(view, in, jobs, scratch, out);
    return out;
  }
};

// The 1D weight of a tap at offset d in {-1, 0, 1}.
double weight(int d) {
  const double side = std::exp(-0.5);
  return (d == 0 ? 1.0 : side) / (1.0 + 2.0 * side);
}

}  // namespace

TEST_CASE("the froxel filter spreads an impulse over the 3x3 Gaussian of its slice, and no further") {
  FilterCase c;
  const FroxelGrid& g = c.grid;
  const int x0 = 4, y0 = 3, k0 = 7;
  std::vector<float> in(g.count(), 0.0f);
  in[g.index(x0, y0, k0)] = 1.0f;
  const std::vector<float>& out = c.filter(in);
  double sum = 0.0;
  for (int y = 0; y < g.ny(); ++y)
    for (int x = 0; x < g.nx(); ++x)
      for (int k = 0; k < g.nz(); ++k) {
        const double v = out[g.index(x, y, k)];
        sum += v;
        const int dx = x - x0, dy = y - y0;
        const bool in_kernel = k == k0 && std::abs(dx) <= 1 && std::abs(dy) <= 1;
        if (!in_kernel) {
          CHECK(v == 0.0);
          continue;
        }
        CAPTURE(dx);
        CAPTURE(dy);
        CHECK(v == doctest::Approx(weight(dx) * weight(dy)).epsilon(1e-6));
      }
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));  // energy kept away from the edges
}

TEST_CASE("the froxel filter keeps a constant slice constant up to the grid's edges (clamped taps)") {
  FilterCase c;
  const FroxelGrid& g = c.grid;
  std::vector<float> in(g.count());
  for (int y = 0; y < g.ny(); ++y)
    for (int x = 0; x < g.nx(); ++x)
      for (int k = 0; k < g.nz(); ++k) in[g.index(x, y, k)] = 0.25f + 0.05f * float(k);
  const std::vector<float>& out = c.filter(in);
  for (size_t i = 0; i < in.size(); ++i) REQUIRE(out[i] == doctest::Approx(in[i]).epsilon(1e-6));
  // At a corner the clamped taps repeat the edge: an impulse there keeps
  // (w0 + w1)^2 of its energy in place.
  std::vector<float> corner(g.count(), 0.0f);
  corner[g.index(0, 0, 3)] = 1.0f;
  const std::vector<float>& at = c.filter(corner);
  CHECK(at[g.index(0, 0, 3)] == doctest::Approx(std::pow(weight(0) + weight(1), 2.0)).epsilon(1e-6));
  CHECK(at[g.index(1, 1, 3)] == doctest::Approx(weight(1) * weight(1)).epsilon(1e-6));
}

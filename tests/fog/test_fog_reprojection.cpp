// reproject_history against its definition. The history clamp, froxel by
// froxel: the history limited to the min/max of the current values in the
// 3x3 columns around (clamped at the grid's edges), in the same slice, over
// the neighbours lit there, then blended, and with a light change the
// history's share scaled by 1 - the 3x3 maximum change; same bits, with depth
// culling cutting columns at random lengths (also at the grid's edges), for
// 24 slices and for 70 (two mask words). And for a moving camera, no
// trilinear read touches a slice the history culled, the history read's
// eight-lane path gives its one-slice definition's bits, and the clamped
// blend reads history only where the clamp range is not one value, with the
// bits of reading every froxel's history. And the geometry itself: each
// froxel centre reads the history where the old camera saw it, projected
// here independently of the pass. The clamp, culled-slice and sparse-read
// tests run on float and on q15 values (sun_term_format.h): the definition
// is written once over the format's lerp.
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <type_traits>

#include "fog/froxel_passes.h"
#include "fog/history_projection.h"
#include "fog/sun_term_format.h"

using namespace cr;

namespace {

// Values in format F (float or q15 codes).
template <class F>
struct ClampCase {
  using Format = F;
  using V = typename F::Value;
  FroxelView view;
  std::vector<V> current, history;
};

template <class F>
ClampCase<F> random_case(unsigned seed, int slices_count = 24) {
  JobSystem jobs(1);
  const FroxelGrid grid(72, 40, 8, slices_count, 0.1f, 48.0f, 0.75f);
  const Camera cam = Camera::look_at({0, 2, 5}, {1, 1, -10}, 1.0f, 72.0f / 40.0f, 0.1f);
  ClampCase<F> c{make_froxel_view(grid, cam, jobs), {}, {}};
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> slices(0, grid.nz());
  // Few distinct values, so ties and zeros of either sign are common.
  std::uniform_int_distribution<int> level(-1, 8);
  for (auto& n : c.view.lit_slices) n = uint16_t(slices(rng));
  c.current.resize(grid.count());
  c.history.resize(grid.count());
  for (auto& v : c.current) v = F::encode(level(rng) < 0 ? -0.0f : float(level(rng)) * 0.125f);
  for (auto& v : c.history) v = F::encode(float(level(rng)) * 0.15f);
  return c;
}

// The case's view from a moved camera, with its columns culled at random lengths.
template <class Case>
FroxelView moved_history_view(const Case& c, std::mt19937& rng) {
  FroxelView history_view = c.view;
  history_view.camera = Camera::look_at({0.4, 2.2, 5.6}, {1.5, 1, -10}, 1.0f, 72.0f / 40.0f, 0.1f);
  std::uniform_int_distribution<int> slices(0, c.view.grid.nz());
  for (auto& n : history_view.lit_slices) n = uint16_t(slices(rng));
  return history_view;
}

// The clamp's definition: the min and max of the current values in the 3x3
// columns around (x, y) (clamped at the grid's edges) in slice j, over the
// neighbours lit there; the froxel itself is lit.
template <class Case, class V>
void range_3x3(const Case& c, const std::vector<V>& values, int x, int y, int j, V& lo, V& hi) {
  const FroxelGrid& g = c.view.grid;
  lo = hi = values[g.index(x, y, j)];
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xn = std::clamp(x + dx, 0, g.nx() - 1), yn = std::clamp(y + dy, 0, g.ny() - 1);
      if (j >= c.view.lit_slices[size_t(yn) * g.nx() + xn]) continue;
      lo = std::min(lo, values[g.index(xn, yn, j)]);
      hi = std::max(hi, values[g.index(xn, yn, j)]);
    }
}
template <class Case, class V = typename Case::V>
void range_3x3(const Case& c, int x, int y, int j, V& lo, V& hi) {
  range_3x3(c, c.current, x, y, j, lo, hi);
}

// The clamped blend of history h at froxel (x, y, j), with the light
// change's 3x3 maximum scaling the history's share where there is one.
template <class Case, class F = typename Case::Format, class V = typename Case::V>
V clamped_blend(const Case& c, const std::vector<V>* light_change, int x, int y, int j, V h, float w) {
  const V cur = c.current[c.view.grid.index(x, y, j)];
  V lo, hi;
  range_3x3(c, x, y, j, lo, hi);
  const V blend = F::lerp(cur, std::min(std::max(h, lo), hi), F::weight(w));
  if (!light_change) return blend;
  V least, most;
  range_3x3(c, *light_change, x, y, j, least, most);
  return F::scale_history_share(cur, blend, most);
}

// Shaft-like current values: blocks of lit (1) and shadowed (0) air with
// scattered values between, so most 3x3 ranges are one value, some are not.
template <class Case>
void shaft_values(Case& c, std::mt19937& rng) {
  const FroxelGrid& g = c.view.grid;
  std::uniform_int_distribution<int> coin(0, 59);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y = 0; y < g.ny(); ++y)
    for (int x = 0; x < g.nx(); ++x)
      for (int k = 0; k < g.nz(); ++k)
        c.current[g.index(x, y, k)] =
            Case::Format::encode(coin(rng) == 0 ? unit(rng) : float((x / 6 + y / 5 + k / 7) % 2));
}

// reproject_history with the clamp and the profile's default weight, on two threads.
constexpr float kWeight = 0.857142857f;
template <class Case, class V = typename Case::V>
ReprojectStats reproject_clamped(const Case& c, const FroxelView& history_view, const std::vector<V>* light_change,
                                 std::vector<V>& out) {
  JobSystem jobs(2);
  return reproject_history(c.view, c.current, history_view, c.history, kWeight, true, jobs, out, light_change);
}

// A light change that is 0 in most froxels and up to 1.5 in the rest.
template <class F>
std::vector<typename F::Value> random_light_change(const FroxelGrid& g, std::mt19937& rng) {
  std::uniform_int_distribution<int> coin(0, 3);
  std::uniform_real_distribution<float> change(0.0f, 1.5f);
  std::vector<typename F::Value> out(g.count());
  for (auto& v : out) v = F::encode(coin(rng) == 0 ? change(rng) : 0.0f);
  return out;
}

// Runs test(c, seed) on the clamp cases: 24 and 70 slices (one and two mask
// words), seeds 1-4, float and q15.
template <class Test>
void for_each_clamp_case(Test&& test) {
  for (int slices_count : {24, 70})
    for (unsigned seed = 1; seed <= 4; ++seed) {
      CAPTURE(slices_count);
      CAPTURE(seed);
      ClampCase<FloatSunTerm> in_float = random_case<FloatSunTerm>(seed, slices_count);
      test(in_float, seed);
      ClampCase<Q15SunTerm> in_q15 = random_case<Q15SunTerm>(seed, slices_count);
      test(in_q15, seed);
    }
}

}  // namespace

TEST_CASE("the reprojection clamp matches the per-froxel 3x3 definition bit for bit") {
  for_each_clamp_case([](auto& c, unsigned seed) {
    using F = typename std::remove_reference_t<decltype(c)>::Format;
    using V = typename F::Value;
    const FroxelGrid& g = c.view.grid;
    // Same camera: the history is read in place where it is lit, so the
    // value before the clamp is known exactly.
    FroxelView history_view = c.view;
    std::mt19937 rng(seed + 100);
    std::uniform_int_distribution<int> slices(0, g.nz());
    for (auto& n : history_view.lit_slices) n = uint16_t(slices(rng));
    // Odd seeds: few distinct values (ties, zeros of either sign); even
    // seeds: shafts of 0 and 1, which the masks pass over, and a light change.
    std::vector<V> light_change;
    if (seed % 2 == 0) {
      shaft_values(c, rng);
      light_change = random_light_change<F>(g, rng);
    }
    const std::vector<V>* change = light_change.empty() ? nullptr : &light_change;
    const float w = kWeight;
    std::vector<V> out;
    const ReprojectStats stats = reproject_clamped(c, history_view, change, out);
    REQUIRE(stats.identity);
    size_t mismatches = 0, rejected = 0, lit = 0;
    for (int y = 0; y < g.ny(); ++y)
      for (int x = 0; x < g.nx(); ++x) {
        const size_t col = size_t(y) * g.nx() + x;
        for (int j = 0; j < c.view.lit_slices[col]; ++j) {
          const V cur = c.current[g.index(x, y, j)];
          const bool has = j < history_view.lit_slices[col];
          const V expected = clamped_blend(c, change, x, y, j, has ? c.history[g.index(x, y, j)] : cur, w);
          mismatches += std::memcmp(&expected, &out[g.index(x, y, j)], sizeof(V)) != 0;
          rejected += !has;
        }
        lit += c.view.lit_slices[col];
      }
    CHECK(mismatches == 0);
    // A still camera streams its history: every froxel is looked up.
    CHECK(stats.reads == lit);
    CHECK(stats.rejected == rejected);
    CHECK(rejected > 0);
  });
}

// Lit history in [0, 1/2] (q15: up to code 16384), culled slices far
// outside (1000, or q15's top code): with no current light, full weight and
// no clamp the output is the history read itself.
template <class F>
void check_culled_slices_unread(unsigned seed) {
  using V = typename F::Value;
  ClampCase<F> c = random_case<F>(seed);
  const FroxelGrid& g = c.view.grid;
  std::mt19937 rng(seed + 200);
  const FroxelView history_view = moved_history_view(c, rng);
  std::uniform_real_distribution<float> unit(0.0f, 0.5f);
  const V culled = std::is_same_v<V, float> ? V(1000) : F::kOne;
  for (int y = 0; y < g.ny(); ++y)
    for (int x = 0; x < g.nx(); ++x)
      for (int j = 0; j < g.nz(); ++j)
        c.history[g.index(x, y, j)] =
            j < history_view.lit_slices[size_t(y) * g.nx() + x] ? F::encode(unit(rng)) : culled;
  std::fill(c.current.begin(), c.current.end(), V(0));
  JobSystem jobs(2);
  std::vector<V> out;
  const ReprojectStats stats = reproject_history(c.view, c.current, history_view, c.history, 1.0f, false, jobs, out);
  REQUIRE_FALSE(stats.identity);
  size_t read = 0, beyond = 0;
  for (size_t col = 0; col < g.columns(); ++col)
    for (int j = 0; j < c.view.lit_slices[col]; ++j) {
      const V h = out[col * g.nz() + size_t(j)];
      read += h > V(0);
      beyond += h > F::encode(0.5f);
    }
  CHECK(read > 0);
  CHECK(beyond == 0);
}

TEST_CASE("a moving camera's history reads never touch a slice the history culled") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    CAPTURE(seed);
    check_culled_slices_unread<FloatSunTerm>(seed);
    check_culled_slices_unread<Q15SunTerm>(seed);
  }
}

TEST_CASE("the moving-camera history read gives its one-slice definition's bits") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    ClampCase<FloatSunTerm> c = random_case<FloatSunTerm>(seed);
    const FroxelGrid& g = c.view.grid;
    std::mt19937 rng(seed + 300);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> coin(0, 3), length(0, g.nz());
    // Most history columns whole, the rest culled at random lengths.
    for (auto& lit : c.view.lit_slices)
      if (coin(rng) != 0) lit = uint16_t(g.nz());
    const HistoryProjection<FloatSunTerm> projection(c.view, c.history);
    HistoryProjection<FloatSunTerm>::Scratch scratch(g.nz());
    std::vector<float> cur(size_t(g.nz())), fast(size_t(g.nz())), definition(size_t(g.nz()));
    size_t last_slice = 0, compared = 0;
    for (int column = 0; column < 400; ++column) {
      // Points anywhere in the grid, some on its last column, row or slice
      // (no neighbour beyond), some outside the history's frustum.
      auto coordinate = [&](int n) { return coin(rng) == 0 ? float(n - 1) : unit(rng) * float(n - 1); };
      for (int k = 0; k < g.nz(); ++k) {
        scratch.fx[size_t(k)] = coordinate(g.nx());
        scratch.fy[size_t(k)] = coordinate(g.ny());
        scratch.fz[size_t(k)] = coordinate(g.nz());
        scratch.inside[size_t(k)] = coin(rng) != 0;
        cur[size_t(k)] = unit(rng);
        last_slice += scratch.fz[size_t(k)] == float(g.nz() - 1);
      }
      const int n = length(rng);
      const size_t rejected = projection.read(scratch, cur.data(), n, fast.data());
      const size_t expected = projection.read_slices(scratch, cur.data(), 0, n, definition.data());
      CHECK(rejected == expected);
      CHECK(std::memcmp(fast.data(), definition.data(), sizeof(float) * size_t(n)) == 0);
      compared += size_t(n) - expected;
    }
    CHECK(last_slice > 0);
    CHECK(compared > 1000);  // many reads that take history, not only rejections
  }
}

TEST_CASE("a moving camera's clamped reprojection reads history only where the 3x3 range is not one value") {
  for_each_clamp_case([](auto& c, unsigned seed) {
    using F = typename std::remove_reference_t<decltype(c)>::Format;
    using V = typename F::Value;
    const FroxelGrid& g = c.view.grid;
    std::mt19937 rng(seed + 400);
    const FroxelView history_view = moved_history_view(c, rng);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (auto& v : c.history) v = F::encode(unit(rng));
    shaft_values(c, rng);
    // Even seeds: the sun moved too.
    const std::vector<V> light_change = seed % 2 == 0 ? random_light_change<F>(g, rng) : std::vector<V>{};
    const std::vector<V>* change = light_change.empty() ? nullptr : &light_change;
    const float w = kWeight;
    std::vector<V> out;
    const ReprojectStats stats = reproject_clamped(c, history_view, change, out);
    REQUIRE_FALSE(stats.identity);
    // The definition: every lit froxel's history projected and read, clamped
    // to its 3x3 range, blended.
    const HistoryProjection<F> projection(history_view, c.history);
    typename HistoryProjection<F>::Scratch scratch(g.nz());
    const Camera& hc = history_view.camera;
    const glm::vec3 offset_world(c.view.camera.position - hc.position);
    const glm::vec3 offset(glm::dot(offset_world, hc.right), glm::dot(offset_world, hc.up),
                           glm::dot(offset_world, hc.forward));
    std::vector<float> centers(size_t(g.nz()));
    std::vector<V> h(size_t(g.nz()));
    for (int k = 0; k < g.nz(); ++k) centers[size_t(k)] = g.center(k);
    size_t lit = 0, mismatches = 0, rejected = 0;
    for (int y = 0; y < g.ny(); ++y)
      for (int x = 0; x < g.nx(); ++x) {
        const size_t col = size_t(y) * g.nx() + x;
        const int n = c.view.lit_slices[col];
        const glm::vec3 d = c.view.directions[col];
        const glm::vec3 dv(glm::dot(d, hc.right), glm::dot(d, hc.up), glm::dot(d, hc.forward));
        projection.project(offset, dv, centers.data(), n, scratch.fx.data(), scratch.fy.data(), scratch.fz.data(),
                           scratch.inside.data());
        const V* cur = c.current.data() + g.index(x, y, 0);
        for (int j = 0; j < n; ++j) {
          const size_t no_history = projection.read_slices(scratch, cur, j, j + 1, h.data());
          V lo, hi;
          range_3x3(c, x, y, j, lo, hi);
          // Where the range is one value the history is not needed: its
          // rejection is not counted.
          if (lo != hi) rejected += no_history;
          const V expected = clamped_blend(c, change, x, y, j, h[size_t(j)], w);
          mismatches += std::memcmp(&expected, &out[g.index(x, y, j)], sizeof(V)) != 0;
        }
        lit += size_t(n);
      }
    CHECK(mismatches == 0);
    // Most froxels' ranges are one value: their history is never looked up.
    CHECK(stats.reads > lit / 10);
    CHECK(stats.reads < lit / 2);
    CHECK(stats.rejected == rejected);
    CHECK(rejected > 0);
  });
}

TEST_CASE("a moving camera reads the history where each froxel centre was, and none outside the old frustum") {
  // The history holds a field linear in its grid's coordinates, which the
  // trilinear read reproduces exactly. Each current froxel centre, projected
  // here with the old camera's own basis (not the pass's code), must read
  // the field at its old grid coordinates; centres the old view did not see
  // keep the current value.
  JobSystem jobs(2);
  const FroxelGrid grid(96, 64, 8, 32, 0.1f, 40.0f, 0.5f);
  const float aspect = 96.0f / 64.0f, vfov = 1.0f;
  const Camera old_cam = Camera::look_at({0, 2, 5}, {1, 1, -10}, vfov, aspect, 0.1f);
  const FroxelView history_view = make_froxel_view(grid, old_cam, jobs);
  const float ax = 1.0f, ay = 3.0f, az = 10.0f, a0 = 7.0f;
  std::vector<float> history(grid.count()), current(grid.count(), -1.0f), out;
  for (int y = 0; y < grid.ny(); ++y)
    for (int x = 0; x < grid.nx(); ++x)
      for (int k = 0; k < grid.nz(); ++k) history[grid.index(x, y, k)] = a0 + ax * x + ay * y + az * k;
  // Moved and turned left and down, then moved back and turned right and up:
  // centres leave the old view past each of its four sides.
  for (const glm::dvec3& target : {glm::dvec3(-4, 1.5, -10), glm::dvec3(8, 5, -10)}) {
    CAPTURE(target.x);
    const Camera cam = Camera::look_at({1.5, 2.4, 3.0 + target.x * 0.3}, target, vfov, aspect, 0.1f);
    const FroxelView view = make_froxel_view(grid, cam, jobs);
    const ReprojectStats stats = reproject_history(view, current, history_view, history, 1.0f, false, jobs, out);
    REQUIRE_FALSE(stats.identity);

    const float tan_y = std::tan(0.5f * vfov), tan_x = tan_y * aspect;
    const float s = float(grid.froxel_size());
    size_t seen = 0, unseen = 0;
    for (int y = 0; y < grid.ny(); ++y)
      for (int x = 0; x < grid.nx(); ++x)
        for (int k = 0; k < grid.nz(); ++k) {
          const glm::vec3 dir = view.directions[size_t(y) * grid.nx() + x];
          const glm::dvec3 p = cam.position + glm::dvec3(dir * grid.center(k));
          const glm::vec3 rel(p - old_cam.position);
          const double qx = glm::dot(rel, old_cam.right), qy = glm::dot(rel, old_cam.up),
                       qz = glm::dot(rel, old_cam.forward);
          const double px = (qx / (qz * tan_x) * 0.5 + 0.5) * grid.width();
          const double py = (0.5 - qy / (qz * tan_y) * 0.5) * grid.height();
          const double dist = glm::length(glm::dvec3(rel));
          const float got = out[grid.index(x, y, k)];
          CAPTURE(x);
          CAPTURE(y);
          CAPTURE(k);
          // Points within a hair of the old frustum's sides or fog range are
          // left to rounding.
          const double margin = 0.01;
          const bool inside = qz > 0 && px > margin && px < grid.width() - margin && py > margin &&
                              py < grid.height() - margin && dist > grid.near_distance() * (1 + 1e-4) &&
                              dist < grid.far_distance() * (1 - 1e-4);
          const bool outside = qz <= 0 || px < -margin || px > grid.width() + margin || py < -margin ||
                               py > grid.height() + margin || dist < grid.near_distance() * (1 - 1e-4) ||
                               dist > grid.far_distance() * (1 + 1e-4);
          if (outside) {
            CHECK(got == -1.0f);
            ++unseen;
          } else if (inside) {
            // Grid coordinates of the point (froxel centres at integers),
            // clamped to the outermost centres as the edge froxels extend.
            const double cx = std::clamp(px / s - 0.5, 0.0, double(grid.nx() - 1));
            const double cy = std::clamp(py / s - 0.5, 0.0, double(grid.ny() - 1));
            const double ck = std::clamp(double(grid.slice_coord(float(dist))) - 0.5, 0.0, double(grid.nz() - 1));
            const double expected = a0 + ax * cx + ay * cy + az * ck;
            // 1e-3 of a froxel laterally and 2e-3 of a slice (the pass's fast log).
            CHECK(std::abs(got - expected) <= ax * 1e-3 + ay * 1e-3 + az * 2e-3 + 1e-4 * expected);
            ++seen;
          }
        }
    // The move leaves both kinds in view.
    CHECK(seen > grid.count() / 4);
    CHECK(unseen > grid.count() / 20);
    CHECK(stats.rejected >= unseen);
  }
}

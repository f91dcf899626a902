// Incremental integration against integrating everything: a column whose
// visibility changed from slice s on keeps its volume before s and continues
// the recurrence from there (float), or is integrated whole (fixed point,
// whose state is wider than what it stores); unchanged columns keep theirs.
// The volume is the full integration's, bit for bit, and only the changed
// tails (float) or columns (fixed point) are integrated.
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <type_traits>

#include "fog/froxel_passes.h"
#include "fog/sun_term_format.h"

using namespace cr;

namespace {

// Visibility in format F, froxels of type Froxel.
template <class F, class Froxel>
void check_incremental(unsigned seed) {
  using V = typename F::Value;
  constexpr bool kResumesInside = std::is_same_v<V, float>;
  JobSystem jobs(2);
  const FroxelGrid grid(96, 64, 8, 40, 0.1f, 48.0f, 0.75f);
  const Camera cam = Camera::look_at({0, 2, 5}, {1, 1, -10}, 1.0f, 96.0f / 64.0f, 0.1f);
  FroxelView view = make_froxel_view(grid, cam, jobs);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> slices(0, grid.nz()), kind(0, 3), level(0, 4);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (auto& n : view.active_slices) n = uint16_t(kind(rng) == 0 ? slices(rng) : grid.nz());
  // Density with clear air, thin and thick froxels.
  std::vector<FogDensity> density(grid.count());
  for (FogDensity& d : density) {
    const float sigma = kind(rng) == 0 ? 0.0f : 0.5f * unit(rng) * unit(rng);
    d = FogDensity{glm::vec3(0.9f, 0.8f, 0.7f) * sigma, sigma};
  }
  auto random_visibility = [&] { return level(rng) == 0 ? unit(rng) : float(level(rng) % 2); };
  std::vector<V> visibility(grid.count());
  for (V& v : visibility) v = F::encode(random_visibility());
  MediumLighting m;
  m.anisotropy = 0.4f;
  m.sun_direction = glm::normalize(glm::vec3(0.3f, 0.8f, -0.2f));
  m.sun_illuminance = glm::vec3(1000.0f, 900.0f, 800.0f);
  m.ambient_sh[0] = glm::vec3(20.0f);
  m.ambient_sh[2] = glm::vec3(5.0f);
  std::vector<Froxel> volume;
  std::vector<V> previous;
  IncrementalIntegration<V> first;
  first.previous = &previous;
  CHECK(integrate_columns(view, density, visibility, m, {}, jobs, volume, first) > 0);
  // Per column: unchanged, changed from a random slice on, or one slice
  // changed (a q15 code may come out the same: fully lit stays 32767).
  const std::vector<V> before = visibility;
  for (size_t c = 0; c < grid.columns(); ++c) {
    const int n = view.active_slices[c];
    if (n == 0) continue;
    const int what = kind(rng) % 3, from = std::uniform_int_distribution<int>(0, n - 1)(rng);
    V* v = visibility.data() + c * grid.nz();
    if (what == 1)
      for (int k = from; k < n; ++k) v[k] = F::encode(0.5f * (F::decode(v[k]) + random_visibility()) + 0.01f);
    if (what == 2) v[from] = F::encode(1.0f - F::decode(v[from]) + 0.25f);
  }
  // From each column's first changed slice on, or the whole of a changed column.
  size_t expected_count = 0;
  for (size_t c = 0; c < grid.columns(); ++c) {
    const int n = view.active_slices[c];
    const size_t base = c * grid.nz();
    int first = 0;
    while (first < n && std::memcmp(&before[base + size_t(first)], &visibility[base + size_t(first)], sizeof(V)) == 0)
      ++first;
    if (first < n) expected_count += size_t(kResumesInside ? n - first : n);
  }
  IncrementalIntegration<V> next;
  next.previous = &previous;
  next.continue_volume = true;
  const size_t integrated = integrate_columns(view, density, visibility, m, {}, jobs, volume, next);
  std::vector<Froxel> full;
  integrate_columns(view, density, visibility, m, {}, jobs, full);
  size_t mismatches = 0, stale = 0;
  for (size_t c = 0; c < grid.columns(); ++c)
    for (int k = 0; k < view.active_slices[c]; ++k) {
      const size_t i = c * grid.nz() + size_t(k);
      mismatches += std::memcmp(&volume[i], &full[i], sizeof(Froxel)) != 0;
      stale += std::memcmp(&previous[i], &visibility[i], sizeof(V)) != 0;
    }
  CHECK(mismatches == 0);
  CHECK(stale == 0);  // previous now holds this visibility
  CHECK(integrated == expected_count);
  size_t active = 0;
  for (uint16_t n : view.active_slices) active += n;
  CHECK(integrated < active);
}

}  // namespace

TEST_CASE("incremental integration gives the full integration's bits and integrates only what changed") {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    CAPTURE(seed);
    check_incremental<FloatSunTerm, IntegratedFroxel>(seed);
    check_incremental<Q15SunTerm, FixedIntegratedFroxel>(seed);
  }
}

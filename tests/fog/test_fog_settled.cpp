// unsettled_spans against the per-froxel definition: a froxel is settled
// where it and every lit froxel of the 3x3x3 box around it (columns and rows
// clamped to the grid, slices k - 1..k + 1) hold the same history value, 0 or
// 1; a column's span runs from its first to its last unsettled lit slice.
// For float histories and q15 ones (whose 1 is code 32767).
#include <doctest/doctest.h>

#include <random>

#include "fog/settled_froxels.h"
#include "fog/sun_term_format.h"

using namespace cr;

namespace {

template <class F, class V = typename F::Value>
std::vector<SliceSpan> definition(const FroxelView& view, const std::vector<V>& h) {
  const FroxelGrid& g = view.grid;
  std::vector<SliceSpan> spans(g.columns());
  for (int y = 0; y < g.ny(); ++y)
    for (int x = 0; x < g.nx(); ++x) {
      const int n = view.lit_slices[size_t(y) * g.nx() + x];
      int first = n, last = -1;
      for (int k = 0; k < n; ++k) {
        const V v = h[g.index(x, y, k)];
        bool settled = v == F::kZero || v == F::kOne;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            for (int dk = -1; dk <= 1; ++dk) {
              const int xn = std::clamp(x + dx, 0, g.nx() - 1), yn = std::clamp(y + dy, 0, g.ny() - 1);
              const int kn = k + dk;
              if (kn < 0 || kn >= view.lit_slices[size_t(yn) * g.nx() + xn]) continue;
              settled = settled && h[g.index(xn, yn, kn)] == v;
            }
        if (!settled) {
          first = std::min(first, k);
          last = k;
        }
      }
      if (last >= 0) spans[size_t(y) * g.nx() + x] = SliceSpan{uint16_t(first), uint16_t(last + 1)};
    }
  return spans;
}

template <class F>
void check_spans(int slices, unsigned seed) {
  JobSystem jobs(2);
  const FroxelGrid grid(256, 160, 8, slices, 0.1f, 48.0f, 0.75f);
  const Camera cam = Camera::look_at({0, 2, 5}, {1, 1, -10}, 1.0f, 256.0f / 160.0f, 0.1f);
  FroxelView view = make_froxel_view(grid, cam, jobs);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coin(0, 3), length(0, slices), rare(0, 40 * slices);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (auto& n : view.lit_slices) n = uint16_t(coin(rng) == 0 ? length(rng) : slices);
  // Blocks of 0 and 1 (lit and shadowed air) with rare values between; in
  // a third of the columns the value also flips along the column at slice
  // 63 and 126, in another third at 64 and 128 (across mask words).
  std::vector<typename F::Value> history(grid.count());
  for (int y = 0; y < grid.ny(); ++y)
    for (int x = 0; x < grid.nx(); ++x)
      for (int k = 0; k < slices; ++k) {
        const int along = (x / 8) % 3 == 0 ? k / 63 : (x / 8) % 3 == 1 ? k / 64 : 0;
        history[grid.index(x, y, k)] = F::encode(rare(rng) == 0 ? unit(rng) : float((x / 8 + y / 6 + along) % 2));
      }
  std::vector<uint64_t> scratch;
  std::vector<SliceSpan> spans;
  unsettled_spans(view, history, jobs, scratch, spans);
  const std::vector<SliceSpan> expected = definition<F>(view, history);
  size_t mismatches = 0, settled_columns = 0, open = 0;
  for (size_t c = 0; c < grid.columns(); ++c) {
    mismatches += spans[c].first != expected[c].first || spans[c].end != expected[c].end;
    settled_columns += expected[c].first == expected[c].end;
    open += size_t(expected[c].end - expected[c].first);
  }
  CHECK(mismatches == 0);
  // Both kinds of column occur, and many froxels lie outside the spans.
  CHECK(settled_columns > 0);
  CHECK(settled_columns < grid.columns());
  size_t lit = 0;
  for (uint16_t n : view.lit_slices) lit += n;
  CHECK(open < 3 * lit / 4);
}

}  // namespace

TEST_CASE("unsettled spans match the per-froxel 3x3x3 definition, for float and q15 histories") {
  // One mask word (24), words around the 64-slice boundary (63, 64, 65),
  // two full words (128) and three, the last partly past the grid (150).
  for (const int slices : {24, 63, 64, 65, 128, 150})
    for (unsigned seed = 1; seed <= 4; ++seed) {
      CAPTURE(slices);
      CAPTURE(seed);
      check_spans<FloatSunTerm>(slices, seed);
      check_spans<Q15SunTerm>(slices, seed);
    }
}

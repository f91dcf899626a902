// unsettled_spans on bit masks: per column and slice word (64 slices), one
// mask of the slices whose history is exactly 0 and one of those exactly 1
// (unlit slices set in both: they do not take part). The 3x3x3 test is then
// separable ANDs of masks: with the column's neighbours in k - 1 and k + 1
// (shifts), then over the three rows, then over the three columns (clamped
// at the grid's edges, which repeats a neighbour: the AND does not change).
// A froxel is settled where either mask keeps its bit.
#include "fog/settled_froxels.h"

#include <algorithm>

#include "fog/slice_masks.h"

namespace cr {

namespace {

template <class V>
void spans_of(const FroxelView& view, const std::vector<V>& history, JobSystem& jobs, std::vector<uint64_t>& scratch,
              std::vector<SliceSpan>& spans) {
  const FroxelGrid& g = view.grid;
  const int nx = g.nx(), ny = g.ny(), nz = g.nz();
  const int words = mask_words(nz);
  const size_t per_column = 2 * size_t(words);  // the 0 masks, then the 1 masks
  spans.resize(g.columns());
  // Per column: the masks ANDed with their neighbours in k - 1 and k + 1.
  scratch.resize(g.columns() * per_column);
  jobs.parallel_for("fog.settled.slices", g.columns(), 64, [&](size_t begin, size_t end) {
    std::vector<uint64_t> m(per_column);
    for (size_t c = begin; c < end; ++c) {
      zero_one_masks(history.data() + c * size_t(nz), view.lit_slices[c], words, m.data());
      uint64_t* out = scratch.data() + c * per_column;
      for (int cls = 0; cls < 2; ++cls) {
        const uint64_t* a = m.data() + size_t(cls * words);
        for (int w = 0; w < words; ++w) {
          const uint64_t below = (a[w] << 1) | (w > 0 ? a[w - 1] >> 63 : 1);
          const uint64_t above = (a[w] >> 1) | (w + 1 < words ? a[w + 1] << 63 : uint64_t(1) << 63);
          out[size_t(cls * words + w)] = a[w] & below & above;
        }
      }
    }
  });
  jobs.parallel_for("fog.settled.columns", size_t(ny), 1, [&](size_t begin, size_t end) {
    std::vector<uint64_t> vertical(size_t(nx) * per_column);
    for (int y = int(begin); y < int(end); ++y) {
      and_rows(scratch.data(), nx, ny, y, words, vertical.data());
      for (int x = 0; x < nx; ++x) {
        const int n = view.lit_slices[size_t(y) * nx + x];
        int first = -1, last = -1;
        for (int w = 0; w < words; ++w) {
          const uint64_t open = mixed_bits(vertical.data(), nx, x, words, w, n);
          if (!open) continue;
          if (first < 0) first = 64 * w + __builtin_ctzll(open);
          last = 64 * w + 63 - __builtin_clzll(open);
        }
        spans[size_t(y) * nx + x] = first < 0 ? SliceSpan{} : SliceSpan{uint16_t(first), uint16_t(last + 1)};
      }
    }
  });
}

}  // namespace

void unsettled_spans(const FroxelView& view, const std::vector<float>& history, JobSystem& jobs,
                     std::vector<uint64_t>& scratch, std::vector<SliceSpan>& spans) {
  spans_of(view, history, jobs, scratch, spans);
}

void unsettled_spans(const FroxelView& view, const std::vector<uint16_t>& history, JobSystem& jobs,
                     std::vector<uint64_t>& scratch, std::vector<SliceSpan>& spans) {
  spans_of(view, history, jobs, scratch, spans);
}

}  // namespace cr

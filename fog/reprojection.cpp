// fog.reproject: temporal accumulation of the jittered sun term.
//
// What is reprojected: only the sun's shadow visibility at the jittered
// sample (one value per froxel, float or q15: sun_term_format.h). Density, the sun's illuminance, ambient
// light and the phase function are evaluated every frame at the froxel
// centre without jitter, so they need no history and cannot ghost; in particular the anisotropic phase
// is applied after the blend with the current view direction, which is exact
// for the one directional light (HDRP reprojects phase-free lighting too, but
// divides a per-light mix back out, which flickers with several lights).
//
// Each froxel centre (world position) is projected with the history's camera
// into the history's grid and read with trilinear interpolation; points
// outside the previous frustum or fog range have no history.
//
// Where the sun moved, the history weight is scaled down by the largest
// light change (light_froxels) in the 3x3 neighbourhood.
//
// With the clamp, a froxel whose 3x3 range is one value (the current froxel
// and its lit neighbours agree) blends to exactly its current value, whatever
// its history and light change. Fully lit and fully shadowed air, 95% of a
// moving valley's froxels, is exactly 1 or 0: bit masks of those values
// (slice_masks.h), ANDed over the 3x3 columns, pass such froxels over whole.
// Only the others get their range, and only those whose range is not one
// value read history (a still camera in place, a moving one projected).
//
// Without the clamp every froxel reads history; the light change's 3x3
// maximum is then separable: per row, each column's maximum over its vertical
// neighbours is computed once into a rotating set of three.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "fog/froxel_passes.h"
#include "fog/history_projection.h"
#include "fog/slice_masks.h"
#include "fog/sun_term_format.h"

namespace cr {

namespace {

// Per slice j < need: the min and max of the three columns a, b, c (one
// above the other) over those whose lit slices include j; the format's
// kAbove / kBelow (+inf / -inf) where none does. Min and max are exact, so
// the range is the reference's whatever the grouping (up to a zero's sign,
// which the clamped blend cannot show).
template <class F, class V = typename F::Value>
void vertical_min_max(const V* a, int lit_a, const V* b, int lit_b, const V* c, int lit_c, int need,
                      V* __restrict lo, V* __restrict hi) {
  const int all = std::min({lit_a, lit_b, lit_c, need});
  for (int j = 0; j < all; ++j) {
    lo[j] = std::min(std::min(a[j], b[j]), c[j]);
    hi[j] = std::max(std::max(a[j], b[j]), c[j]);
  }
  std::fill(lo + all, lo + std::max(all, need), F::kAbove);
  std::fill(hi + all, hi + std::max(all, need), F::kBelow);
  for (const auto& [col, lit] : {std::pair{a, lit_a}, std::pair{b, lit_b}, std::pair{c, lit_c}})
    for (int j = all; j < std::min(lit, need); ++j) {
      lo[j] = std::min(lo[j], col[j]);
      hi[j] = std::max(hi[j], col[j]);
    }
}

// Per slice j < need: the largest of columns a, b, c (one above the other)
// over those whose lit slices include j; 0 where none does.
template <class F, class V = typename F::Value>
void vertical_max(const V* a, int lit_a, const V* b, int lit_b, const V* c, int lit_c, int need,
                  V* __restrict out) {
  const int all = std::min({lit_a, lit_b, lit_c, need});
  for (int j = 0; j < all; ++j) out[j] = std::max(std::max(a[j], b[j]), c[j]);
  std::fill(out + all, out + std::max(all, need), F::kZero);
  for (const auto& [col, lit] : {std::pair{a, lit_a}, std::pair{b, lit_b}, std::pair{c, lit_c}})
    for (int j = all; j < std::min(lit, need); ++j) out[j] = std::max(out[j], col[j]);
}

// The 3x3 columns around one (clamped at the grid's edges) in its slice
// plane: where each starts and how many slices it has lit.
struct Neighbourhood {
  size_t base[9];
  int lit[9];

  Neighbourhood(const FroxelView& view, int x, int y) {
    const FroxelGrid& g = view.grid;
    const int xs[3] = {std::max(x - 1, 0), x, std::min(x + 1, g.nx() - 1)};
    const int ys[3] = {std::max(y - 1, 0), y, std::min(y + 1, g.ny() - 1)};
    for (int i = 0; i < 9; ++i) {
      const size_t c = size_t(ys[i / 3]) * size_t(g.nx()) + size_t(xs[i % 3]);
      base[i] = c * size_t(g.nz());
      lit[i] = view.lit_slices[c];
    }
  }
  // The min and max of `values` at slice j over the columns lit there (the
  // middle one is; an unlit one counts as it, without a branch). Min and
  // max are exact, so any grouping gives the same range (up to a zero's
  // sign, which the clamped blend cannot show).
  template <class V>
  void range(const V* values, int j, V& lo, V& hi) const {
    const V middle = values[base[4] + size_t(j)];
    V l = middle, h = middle;
    for (int i = 0; i < 9; ++i) {
      const V read = values[base[i] + size_t(j)];  // in the grid, perhaps stale: selected away
      const V v = j < lit[i] ? read : middle;
      l = std::min(l, v);
      h = std::max(h, v);
    }
    lo = l;
    hi = h;
  }
};

}  // namespace

bool same_view(const FroxelView& a, const FroxelView& b) {
  const Camera &p = a.camera, &q = b.camera;
  return p.position == q.position && p.forward == q.forward && p.up == q.up && p.right == q.right &&
         p.vfov_rad == q.vfov_rad && p.aspect == q.aspect && p.znear == q.znear && a.grid.same_layout(b.grid);
}

namespace {

template <class F, class V = typename F::Value>
ReprojectStats reproject(const FroxelView& view, const std::vector<V>& current, const FroxelView& history_view,
                         const std::vector<V>& history, float history_weight, bool clamp, JobSystem& jobs,
                         std::vector<V>& out, const std::vector<V>* light_change) {
  const FroxelGrid& g = view.grid;
  out.resize(g.count());
  ReprojectStats stats;
  const typename F::Weight w = F::weight(history_weight);
  stats.identity = same_view(view, history_view);
  const Camera& hc = history_view.camera;
  // Froxel centre in the history camera's view: q(t) = offset + t * R dir.
  const glm::vec3 offset_world(view.camera.position - hc.position);
  const glm::vec3 offset(glm::dot(offset_world, hc.right), glm::dot(offset_world, hc.up),
                         glm::dot(offset_world, hc.forward));
  std::optional<HistoryProjection<F>> projection;  // set up only for a moved camera
  if (!stats.identity) projection.emplace(history_view, history);
  const int nx = g.nx(), ny = g.ny(), nz = g.nz();
  std::vector<float> centers(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) centers[size_t(k)] = g.center(k);
  std::vector<size_t> rejected_per_row(size_t(ny), 0), reads_per_row(size_t(ny), 0), clamped_per_row(size_t(ny), 0);
  // Per column the slices are contiguous values, so the blends run as flat
  // loops the compiler vectorises.
  const V* cur_all = current.data();
  const V* hist_all = history.data();
  V* out_all = out.data();
  const uint16_t* lit_all = view.lit_slices.data();
  const V* change_all = light_change ? light_change->data() : nullptr;
  // A moving camera with the clamp reads history only where the range is
  // not one value: per column, the slices whose current value is exactly 0
  // and exactly 1 (slice_masks.h) find the others.
  const bool sparse = clamp && !stats.identity;
  const int words = mask_words(nz);
  const size_t per_column = 2 * size_t(words);
  std::vector<uint64_t> masks(sparse ? g.columns() * per_column : 0);
  if (sparse)
    jobs.parallel_for("fog.reproject.masks", g.columns(), 256, [&](size_t begin, size_t end) {
      for (size_t c = begin; c < end; ++c)
        zero_one_masks(cur_all + c * size_t(nz), lit_all[c], words, masks.data() + c * per_column);
    });
  jobs.parallel_for("fog.reproject", size_t(ny), 1, [&](size_t begin, size_t end) {
    typename HistoryProjection<F>::Scratch scratch(nz);
    // Streamed (every froxel's history): a column's history, and the clamp
    // range and light change of three neighbouring columns (vertical
    // minima, maxima), rotated along the row.
    std::vector<V> h(sparse ? 0 : static_cast<size_t>(nz));
    std::vector<V> range_lo(clamp && !sparse ? 3 * static_cast<size_t>(nz) : 0), range_hi(range_lo.size());
    std::vector<V> change_max(light_change && !sparse ? 3 * static_cast<size_t>(nz) : 0);
    // Sparse: the row's masks ANDed over the three rows, and a column's
    // slices whose range is not one value: their slice, range, centre,
    // current value and history.
    std::vector<uint64_t> vertical(sparse ? size_t(nx) * per_column : 0);
    std::vector<int> open(sparse ? static_cast<size_t>(nz) : 0);
    std::vector<V> open_lo(open.size()), open_hi(open.size()), open_cur(open.size()), open_h(open.size());
    std::vector<float> open_t(open.size());
    for (int y = int(begin); y < int(end); ++y) {
      // The row's counts, stored once (rows of other jobs share cache lines).
      size_t reads = 0, rejected = 0, clamped_count = 0;
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, ny - 1);
      const uint16_t* lit_row = lit_all + size_t(y) * nx;
      // The slices any of xc - 1, xc, xc + 1 produces.
      auto need_of = [&](int xc) {
        return int(std::max({lit_row[std::max(xc - 1, 0)], lit_row[xc], lit_row[std::min(xc + 1, nx - 1)]}));
      };
      // Range of column xc of this row and its vertical neighbours over the
      // slices any of xc - 1, xc, xc + 1 produces, into slot xc mod 3.
      auto vertical_range = [&](int xc) {
        vertical_min_max<F>(cur_all + g.index(xc, ya, 0), lit_all[size_t(ya) * nx + xc], cur_all + g.index(xc, y, 0),
                         lit_row[xc], cur_all + g.index(xc, yb, 0), lit_all[size_t(yb) * nx + xc], need_of(xc),
                         range_lo.data() + size_t(xc % 3) * nz, range_hi.data() + size_t(xc % 3) * nz);
      };
      auto vertical_change = [&](int xc) {
        vertical_max<F>(change_all + g.index(xc, ya, 0), lit_all[size_t(ya) * nx + xc], change_all + g.index(xc, y, 0),
                     lit_row[xc], change_all + g.index(xc, yb, 0), lit_all[size_t(yb) * nx + xc], need_of(xc),
                     change_max.data() + size_t(xc % 3) * nz);
      };
      if (sparse) {
        and_rows(masks.data(), nx, ny, y, words, vertical.data());
      } else {
        if (clamp) vertical_range(0);
        if (light_change) vertical_change(0);
      }
      for (int x = 0; x < nx; ++x) {
        const size_t c = size_t(y) * nx + x;
        const int n = lit_row[x];
        const size_t base = g.index(x, y, 0);
        const V* cur = cur_all + base;
        V* dst = out_all + base;
        // Clamp the history to the range of the current frame's 3x3
        // neighbourhood in this slice (TAA-style): neighbours sample other
        // depth strata (column hash), so their range brackets the converged
        // value; history outside it is a ghost (moved shaft, disocclusion)
        // and is cut. HDRP does not clamp. Neighbours count only where they
        // are lit.
        if (sparse) {
          // The light change is read sparsely, which the hardware prefetcher
          // does not follow: the column two ahead is requested now.
          if (change_all && x + 2 < nx)
            for (int j = 0; j < nz; j += 16)
              for (int yy : {ya, y, yb}) __builtin_prefetch(change_all + g.index(x + 2, yy, j));
          // A froxel whose range is one value blends to its current value:
          // lerp(cur, clamped, w) with clamped == cur. Those whose range is
          // not one value are overwritten below.
          for (int j = 0; j < n; ++j) dst[j] = F::blend_with_itself(cur[j]);
          int count = 0;
          std::optional<Neighbourhood> around;
          for (int wi = 0; wi < words; ++wi)
            for (uint64_t rest = mixed_bits(vertical.data(), nx, x, words, wi, n); rest != 0; rest &= rest - 1) {
              const int j = 64 * wi + __builtin_ctzll(rest);
              if (!around) around.emplace(view, x, y);
              V lo, hi;
              around->range(cur_all, j, lo, hi);
              if (lo == hi) continue;
              open[size_t(count)] = j;
              open_lo[size_t(count)] = lo;
              open_hi[size_t(count)] = hi;
              ++count;
            }
          if (count == 0) continue;
          reads += size_t(count);
          // Their history, projected into the history's grid (where there is
          // none the current value stands in, which the blend keeps).
          const glm::vec3 d = view.directions[c];
          const glm::vec3 dv(glm::dot(d, hc.right), glm::dot(d, hc.up), glm::dot(d, hc.forward));
          for (int i = 0; i < count; ++i) {
            open_t[size_t(i)] = centers[size_t(open[size_t(i)])];
            open_cur[size_t(i)] = cur[open[size_t(i)]];
          }
          projection->project(offset, dv, open_t.data(), count, scratch.fx.data(), scratch.fy.data(),
                              scratch.fz.data(), scratch.inside.data());
          rejected += projection->read(scratch, open_cur.data(), count, open_h.data());
          for (int i = 0; i < count; ++i) {
            const int j = open[size_t(i)];
            const V now = open_cur[size_t(i)];
            const V clamped = std::min(std::max(open_h[size_t(i)], open_lo[size_t(i)]), open_hi[size_t(i)]);
            clamped_count += size_t(clamped != open_h[size_t(i)]);
            V v = F::lerp(now, clamped, w);
            if (change_all) {
              // The blend's history share scaled by 1 - the 3x3
              // neighbourhood's largest light change.
              V least, most;
              around->range(change_all, j, least, most);
              v = F::scale_history_share(now, v, most);
            }
            dst[j] = v;
          }
          continue;
        }
        // Streamed: the history of every slice, read in place for the same
        // camera (the slices it lacks take the current value), else
        // projected into h.
        const V* hist = h.data();
        if (stats.identity) {
          const int kept = std::min(n, int(history_view.lit_slices[c]));
          if (kept < n) {
            std::copy(hist_all + base, hist_all + base + size_t(kept), h.data());
            std::copy(cur + kept, cur + n, h.data() + kept);
          } else {
            hist = hist_all + base;
          }
          rejected += size_t(n - kept);
        } else {
          const glm::vec3 d = view.directions[c];
          const glm::vec3 dv(glm::dot(d, hc.right), glm::dot(d, hc.up), glm::dot(d, hc.forward));
          projection->project(offset, dv, centers.data(), n, scratch.fx.data(), scratch.fy.data(),
                              scratch.fz.data(), scratch.inside.data());
          rejected += projection->read(scratch, cur, n, h.data());
        }
        reads += size_t(n);
        if (clamp) {
          // The range combines the vertical ranges of columns x - 1, x, x + 1
          // (clamped at the edges).
          if (x + 1 < nx) vertical_range(x + 1);  // into the slot x - 2 used
          const V* lo = range_lo.data();
          const V* hi = range_hi.data();
          const size_t left = size_t(std::max(x - 1, 0) % 3) * nz, mid = size_t(x % 3) * nz,
                       right = size_t(std::min(x + 1, nx - 1) % 3) * nz;
          for (int j = 0; j < n; ++j) {
            const V l = std::min(std::min(lo[left + j], lo[mid + j]), lo[right + j]);
            const V u = std::max(std::max(hi[left + j], hi[mid + j]), hi[right + j]);
            const V clamped = std::min(std::max(hist[j], l), u);
            clamped_count += size_t(clamped != hist[j]);
            dst[j] = F::lerp(cur[j], clamped, w);
          }
        } else {
          for (int j = 0; j < n; ++j) dst[j] = F::lerp(cur[j], hist[j], w);
        }
        if (light_change) {
          // The blend's history share scaled by 1 - the 3x3 neighbourhood's largest light change.
          if (x + 1 < nx) vertical_change(x + 1);  // into the slot x - 2 used
          const V* left = change_max.data() + size_t(std::max(x - 1, 0) % 3) * nz;
          const V* mid = change_max.data() + size_t(x % 3) * nz;
          const V* right = change_max.data() + size_t(std::min(x + 1, nx - 1) % 3) * nz;
          for (int j = 0; j < n; ++j)
            dst[j] = F::scale_history_share(cur[j], dst[j], std::max(std::max(left[j], mid[j]), right[j]));
        }
      }
      reads_per_row[size_t(y)] = reads;
      rejected_per_row[size_t(y)] = rejected;
      clamped_per_row[size_t(y)] = clamped_count;
    }
  });
  for (size_t r : rejected_per_row) stats.rejected += r;
  for (size_t r : reads_per_row) stats.reads += r;
  for (size_t r : clamped_per_row) stats.clamped += r;
  return stats;
}

}  // namespace

ReprojectStats reproject_history(const FroxelView& view, const std::vector<float>& current,
                                 const FroxelView& history_view, const std::vector<float>& history,
                                 float history_weight, bool clamp, JobSystem& jobs, std::vector<float>& out,
                                 const std::vector<float>* light_change) {
  return reproject<FloatSunTerm>(view, current, history_view, history, history_weight, clamp, jobs, out,
                                 light_change);
}

ReprojectStats reproject_history(const FroxelView& view, const std::vector<uint16_t>& current,
                                 const FroxelView& history_view, const std::vector<uint16_t>& history,
                                 float history_weight, bool clamp, JobSystem& jobs, std::vector<uint16_t>& out,
                                 const std::vector<uint16_t>* light_change) {
  return reproject<Q15SunTerm>(view, current, history_view, history, history_weight, clamp, jobs, out,
                               light_change);
}

}  // namespace cr

// fog.reproject: temporal accumulation of the jittered sun term.
//
// What is reprojected: only the sun's shadow visibility at the jittered
// sample (one float per froxel). Density, the sun's illuminance, ambient
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
// light change (light_froxels) in the 3x3 neighbourhood, kept in the same
// rotating per-column form as the clamp's range.
//
// The clamp's 3x3 range is separable: per row, each column's min/max over
// its vertical neighbours is computed once into a rotating set of three,
// and a froxel's range combines those of its column and the two beside it
// (6 reads per slice instead of 9 read-modify-writes of running bounds).
//
// With the clamp, a froxel whose 3x3 range is one value (the current froxel
// and its lit neighbours agree: fully lit or fully shadowed air, 95% of a
// moving valley's froxels) blends to exactly its current value, whatever
// its history: a moving camera projects and reads history only for the
// others.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "fog/froxel_passes.h"
#include "fog/history_projection.h"

namespace cr {

namespace {


// Per slice j < need: the min and max of the three columns a, b, c (one
// above the other) over those whose lit slices include j; +inf / -inf where
// none does. Min and max are exact, so the range is the reference's whatever
// the grouping (up to a zero's sign, which the clamped blend cannot show).
void vertical_min_max(const float* a, int lit_a, const float* b, int lit_b, const float* c, int lit_c, int need,
                      float* __restrict lo, float* __restrict hi) {
  const int all = std::min({lit_a, lit_b, lit_c, need});
  for (int j = 0; j < all; ++j) {
    lo[j] = std::min(std::min(a[j], b[j]), c[j]);
    hi[j] = std::max(std::max(a[j], b[j]), c[j]);
  }
  std::fill(lo + all, lo + std::max(all, need), INFINITY);
  std::fill(hi + all, hi + std::max(all, need), -INFINITY);
  for (const auto& [col, lit] : {std::pair{a, lit_a}, std::pair{b, lit_b}, std::pair{c, lit_c}})
    for (int j = all; j < std::min(lit, need); ++j) {
      lo[j] = std::min(lo[j], col[j]);
      hi[j] = std::max(hi[j], col[j]);
    }
}

// Per slice j < need: the largest of columns a, b, c (one above the other)
// over those whose lit slices include j; 0 where none does.
void vertical_max(const float* a, int lit_a, const float* b, int lit_b, const float* c, int lit_c, int need,
                  float* __restrict out) {
  const int all = std::min({lit_a, lit_b, lit_c, need});
  for (int j = 0; j < all; ++j) out[j] = std::max(std::max(a[j], b[j]), c[j]);
  std::fill(out + all, out + std::max(all, need), 0.0f);
  for (const auto& [col, lit] : {std::pair{a, lit_a}, std::pair{b, lit_b}, std::pair{c, lit_c}})
    for (int j = all; j < std::min(lit, need); ++j) out[j] = std::max(out[j], col[j]);
}

}  // namespace

bool same_view(const FroxelView& a, const FroxelView& b) {
  const Camera &p = a.camera, &q = b.camera;
  return p.position == q.position && p.forward == q.forward && p.up == q.up && p.right == q.right &&
         p.vfov_rad == q.vfov_rad && p.aspect == q.aspect && p.znear == q.znear && a.grid.same_layout(b.grid);
}

ReprojectStats reproject_history(const FroxelView& view, const std::vector<float>& current,
                                 const FroxelView& history_view, const std::vector<float>& history,
                                 float history_weight, bool clamp, JobSystem& jobs, std::vector<float>& out,
                                 const std::vector<float>* light_change) {
  const FroxelGrid& g = view.grid;
  out.resize(g.count());
  ReprojectStats stats;
  const float w = history_weight;
  stats.identity = same_view(view, history_view);
  const Camera& hc = history_view.camera;
  // Froxel centre in the history camera's view: q(t) = offset + t * R dir.
  const glm::vec3 offset_world(view.camera.position - hc.position);
  const glm::vec3 offset(glm::dot(offset_world, hc.right), glm::dot(offset_world, hc.up),
                         glm::dot(offset_world, hc.forward));
  std::optional<HistoryProjection> projection;  // set up only for a moved camera
  if (!stats.identity) projection.emplace(history_view, history);
  const int nx = g.nx(), ny = g.ny(), nz = g.nz();
  std::vector<float> centers(static_cast<size_t>(nz));
  for (int k = 0; k < nz; ++k) centers[size_t(k)] = g.center(k);
  std::vector<size_t> rejected_per_row(size_t(ny), 0), reads_per_row(size_t(ny), 0);
  // Per column the slices are contiguous floats, so the clamp and blend run
  // as flat loops the compiler vectorises.
  const float* cur_all = current.data();
  const float* hist_all = history.data();
  float* out_all = out.data();
  const uint16_t* lit_all = view.lit_slices.data();
  jobs.parallel_for("fog.reproject", size_t(ny), 1, [&](size_t begin, size_t end) {
    std::vector<float> h(static_cast<size_t>(nz));
    // Clamp range of three neighbouring columns, rotated along the row.
    std::vector<float> range_lo(3 * static_cast<size_t>(nz)), range_hi(3 * static_cast<size_t>(nz));
    HistoryProjection::Scratch scratch(nz);
    // With the clamp, a moving camera's slices whose range is not one value:
    // their centres, current values and history.
    const size_t sparse = clamp && !stats.identity ? size_t(nz) : 0;
    std::vector<int> open(sparse);
    std::vector<float> open_t(sparse), open_cur(sparse), open_h(sparse);
    // Light change of three neighbouring columns (vertical maxima), rotated the same way.
    std::vector<float> change_max(light_change ? 3 * static_cast<size_t>(nz) : 0);
    for (int y = int(begin); y < int(end); ++y) {
      // The row's counts, stored once (rows of other jobs share cache lines).
      size_t reads = 0, rejected_in_row = 0;
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, ny - 1);
      const uint16_t* lit_row = lit_all + size_t(y) * nx;
      // The slices any of xc - 1, xc, xc + 1 produces.
      auto need_of = [&](int xc) {
        return int(std::max({lit_row[std::max(xc - 1, 0)], lit_row[xc], lit_row[std::min(xc + 1, nx - 1)]}));
      };
      // Range of column xc of this row and its vertical neighbours over the
      // slices any of x - 1, x, x + 1 produces, into slot xc mod 3.
      auto vertical_range = [&](int xc) {
        const int need = need_of(xc);
        vertical_min_max(cur_all + g.index(xc, ya, 0), lit_all[size_t(ya) * nx + xc],
                         cur_all + g.index(xc, y, 0), lit_row[xc], cur_all + g.index(xc, yb, 0),
                         lit_all[size_t(yb) * nx + xc], need, range_lo.data() + size_t(xc % 3) * nz,
                         range_hi.data() + size_t(xc % 3) * nz);
      };
      auto vertical_change = [&](int xc) {
        const int need = need_of(xc);
        const float* lc = light_change->data();
        vertical_max(lc + g.index(xc, ya, 0), lit_all[size_t(ya) * nx + xc], lc + g.index(xc, y, 0), lit_row[xc],
                     lc + g.index(xc, yb, 0), lit_all[size_t(yb) * nx + xc], need,
                     change_max.data() + size_t(xc % 3) * nz);
      };
      if (clamp) vertical_range(0);
      if (light_change) vertical_change(0);
      for (int x = 0; x < nx; ++x) {
        const size_t c = size_t(y) * nx + x;
        const int n = lit_row[x];
        const size_t base = g.index(x, y, 0);
        const float* cur = cur_all + base;
        float* dst = out_all + base;
        // History per slice; where there is none it takes the current value,
        // which the clamp keeps and the blend returns unchanged.
        const size_t len = size_t(n);
        // The clamp's slots of columns x - 1, x, x + 1 (clamped at the edges).
        const size_t left = size_t(std::max(x - 1, 0) % 3) * nz, mid = size_t(x % 3) * nz,
                     right = size_t(std::min(x + 1, nx - 1) % 3) * nz;
        const float* lo = range_lo.data();
        const float* hi = range_hi.data();
        // Slice j's clamp range is one value (the current one).
        auto one_value = [&](size_t j) {
          return std::min(std::min(lo[left + j], lo[mid + j]), lo[right + j]) ==
                 std::max(std::max(hi[left + j], hi[mid + j]), hi[right + j]);
        };
        if (clamp) {
          // Clamp the history to the range of the current frame's 3x3
          // neighbourhood in this slice (TAA-style): neighbours sample other
          // depth strata (column hash), so their range brackets the
          // converged value; history outside it is a ghost (moved shaft,
          // disocclusion) and is cut. HDRP does not clamp. Neighbours count
          // only where they are lit. The range is the columns' vertical
          // ranges combined across x - 1, x, x + 1 (clamped at the edges).
          if (x + 1 < nx) vertical_range(x + 1);  // into the slot x - 2 used
        }
        size_t rejected = 0;
        // The history of the slices: read in place for the same camera (the
        // slices it lacks take the current value), else gathered into h.
        const float* hist = h.data();
        if (stats.identity) {
          const int m = std::min(n, int(history_view.lit_slices[c]));
          if (m < n) {
            std::copy(hist_all + base, hist_all + base + size_t(m), h.data());
            std::copy(cur + m, cur + n, h.data() + m);
          } else {
            hist = hist_all + base;
          }
          rejected = size_t(n - m);
          reads += len;
        } else {
          const glm::vec3 d = view.directions[c];
          const glm::vec3 dv(glm::dot(d, hc.right), glm::dot(d, hc.up), glm::dot(d, hc.forward));
          if (clamp) {
            // Only the slices whose range is not one value read history; the
            // others keep the current value, which the clamp would give.
            // Blocks of 8 slices where all agree (most) are passed over whole.
            int m = 0;
            for (int j0 = 0; j0 < n; j0 += 8) {
              const int e = std::min(j0 + 8, n);
              int differ = 0;
              for (int j = j0; j < e; ++j) differ |= int(!one_value(size_t(j)));
              if (!differ) continue;
              for (int j = j0; j < e; ++j) {
                open[size_t(m)] = j;
                m += !one_value(size_t(j));
              }
            }
            for (int i = 0; i < m; ++i) {
              open_t[size_t(i)] = centers[size_t(open[size_t(i)])];
              open_cur[size_t(i)] = cur[open[size_t(i)]];
            }
            projection->project(offset, dv, open_t.data(), m, scratch.fx.data(), scratch.fy.data(),
                               scratch.fz.data(), scratch.inside.data());
            rejected = projection->read(scratch, open_cur.data(), m, open_h.data());
            std::copy(cur, cur + n, h.data());
            for (int i = 0; i < m; ++i) h[size_t(open[size_t(i)])] = open_h[size_t(i)];
            reads += size_t(m);
          } else {
            projection->project(offset, dv, centers.data(), n, scratch.fx.data(), scratch.fy.data(),
                               scratch.fz.data(), scratch.inside.data());
            rejected = projection->read(scratch, cur, n, h.data());
            reads += len;
          }
        }
        rejected_in_row += rejected;
        if (clamp) {
          for (size_t j = 0; j < len; ++j) {
            const float l = std::min(std::min(lo[left + j], lo[mid + j]), lo[right + j]);
            const float u = std::max(std::max(hi[left + j], hi[mid + j]), hi[right + j]);
            const float clamped = std::min(std::max(hist[j], l), u);
            dst[j] = cur[j] + (clamped - cur[j]) * w;
          }
        } else {
          for (size_t j = 0; j < len; ++j) dst[j] = cur[j] + (hist[j] - cur[j]) * w;
        }
        if (light_change) {
          // The blend's history share scaled by 1 - the 3x3 neighbourhood's largest light change.
          if (x + 1 < nx) vertical_change(x + 1);
          const float* left = change_max.data() + size_t(std::max(x - 1, 0) % 3) * nz;
          const float* mid = change_max.data() + size_t(x % 3) * nz;
          const float* right = change_max.data() + size_t(std::min(x + 1, nx - 1) % 3) * nz;
          for (size_t j = 0; j < len; ++j) {
            const float m = std::min(std::max(std::max(left[j], mid[j]), right[j]), 1.0f);
            dst[j] = cur[j] + (dst[j] - cur[j]) * (1.0f - m);
          }
        }
      }
      reads_per_row[size_t(y)] = reads;
      rejected_per_row[size_t(y)] = rejected_in_row;
    }
  });
  for (size_t r : rejected_per_row) stats.rejected += r;
  for (size_t r : reads_per_row) stats.reads += r;
  return stats;
}

}  // namespace cr

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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "fog/fast_log.h"
#include "fog/froxel_passes.h"

namespace cr {

namespace {

// Projection of a column's froxel centres into the history's grid, set up
// once per frame. A column's centres lie on one line, q(t) = offset + t dv in
// the history camera's frame (right, up, forward, relative to its position),
// so the projection runs as flat loops over the slices (the slice encoding's
// log is fast_log, which vectorises), then the trilinear reads per slice.
struct HistoryProjection {
  const FroxelGrid* grid;
  const float* values;
  // Per history column (x0, y0): the fewest slices the 2x2 columns x0..x1,
  // y0..y1 of a trilinear read from there hold (x1, y1 clamped to the grid).
  std::vector<uint16_t> lit_2x2;
  float scale_x, scale_y;  // pixels per unit of x/z and y/z
  float half_w, half_h;    // screen centre in pixels
  float max_px, max_py;    // grid extent in pixels
  float inv_size;          // 1 / froxel size

  HistoryProjection(const FroxelView& hv, const std::vector<float>& history) {
    grid = &hv.grid;
    values = history.data();
    const int nx = grid->nx(), ny = grid->ny();
    lit_2x2.resize(grid->columns());
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const int x1 = std::min(x + 1, nx - 1), y1 = std::min(y + 1, ny - 1);
        lit_2x2[size_t(y) * nx + x] = std::min({hv.lit_slices[size_t(y) * nx + x], hv.lit_slices[size_t(y) * nx + x1],
                                                hv.lit_slices[size_t(y1) * nx + x], hv.lit_slices[size_t(y1) * nx + x1]});
      }
    const float tan_y = std::tan(0.5f * hv.camera.vfov_rad);
    scale_x = 0.5f * float(grid->width()) / (tan_y * hv.camera.aspect);
    scale_y = 0.5f * float(grid->height()) / tan_y;
    half_w = 0.5f * float(grid->width());
    half_h = 0.5f * float(grid->height());
    inv_size = 1.0f / float(grid->froxel_size());
    max_px = float(grid->nx() * grid->froxel_size());
    max_py = float(grid->ny() * grid->froxel_size());
  }

  // Per-slice scratch of one job: continuous froxel-centre coordinates in the
  // history grid and whether the point lies inside its frustum and fog range.
  struct Scratch {
    std::vector<float> fx, fy, fz;
    std::vector<int32_t> inside;
    explicit Scratch(int nz) : fx(size_t(nz)), fy(size_t(nz)), fz(size_t(nz)), inside(size_t(nz)) {}
  };

  // Projection of slices [0, n) at distances t: branch-free, vectorised.
  void project(const glm::vec3& offset, const glm::vec3& dv, const float* __restrict t, int n,
               float* __restrict fx_out, float* __restrict fy_out, float* __restrict fz_out,
               int32_t* __restrict inside_out) const {
    const FroxelGrid& hg = *grid;
    const float near = hg.near_distance(), far = hg.far_distance();
    const float log_c = hg.log_c(), log_scale = hg.log_scale();
    const float last_x = float(hg.nx() - 1), last_y = float(hg.ny() - 1), last_z = float(hg.nz() - 1);
    for (int k = 0; k < n; ++k) {
      const float qx = offset.x + dv.x * t[k], qy = offset.y + dv.y * t[k], qz = offset.z + dv.z * t[k];
      const bool ahead = qz > 0.0f;
      const float inv_z = 1.0f / (ahead ? qz : 1.0f);
      const float px = qx * inv_z * scale_x + half_w;
      const float py = half_h - qy * inv_z * scale_y;
      const float dist = std::sqrt(qx * qx + qy * qy + qz * qz);
      inside_out[k] = ahead & (px >= 0.0f) & (py >= 0.0f) & (px <= max_px) & (py <= max_py) & (dist >= near) &
                      (dist <= far);
      fx_out[k] = std::min(std::max(px * inv_size - 0.5f, 0.0f), last_x);
      fy_out[k] = std::min(std::max(py * inv_size - 0.5f, 0.0f), last_y);
      const float d = std::min(std::max(dist, near), far);
      fz_out[k] = std::min(std::max(fast_log(1.0f + log_c * (d - near)) * log_scale - 0.5f, 0.0f), last_z);
    }
  }

  // h[k] = the trilinear history at slice k's projected point, or cur[k]
  // where there is none (outside the history's frustum or fog range, or a
  // corner the history culled). Returns how many slices had none.
  size_t read(const Scratch& s, const float* cur, int n, float* h) const {
    const FroxelGrid& hg = *grid;
    const int nx = hg.nx(), ny = hg.ny(), nz = hg.nz();
    size_t rejected = 0;
    for (int k = 0; k < n; ++k) {
      const float fx = s.fx[size_t(k)], fy = s.fy[size_t(k)], fz = s.fz[size_t(k)];
      const int x0 = int(fx), y0 = int(fy), z0 = int(fz);
      const int x1 = std::min(x0 + 1, nx - 1), y1 = std::min(y0 + 1, ny - 1);
      if (k % 8 == 0) {
        // The history two columns to the right at this point: what the next
        // columns of the row read here. The row's reads wander over several
        // history rows, which the hardware prefetcher does not follow.
        const int xp = std::min(x0 + 2, nx - 1);
        __builtin_prefetch(values + hg.index(xp, y0, z0));
        __builtin_prefetch(values + hg.index(xp, y1, z0));
      }
      const int dz = z0 + 1 < nz ? 1 : 0;
      const int need = z0 + dz + 1;
      if (!s.inside[size_t(k)] || lit_2x2[size_t(y0) * nx + x0] < need) {
        h[k] = cur[k];
        ++rejected;
        continue;
      }
      const float ax = fx - float(x0), ay = fy - float(y0), az = fz - float(z0);
      auto lerp_z = [&](int xi, int yi) {
        const float* c = values + hg.index(xi, yi, z0);
        return c[0] + (c[dz] - c[0]) * az;
      };
      const float v00 = lerp_z(x0, y0), v10 = lerp_z(x1, y0), v01 = lerp_z(x0, y1), v11 = lerp_z(x1, y1);
      const float v0 = v00 + (v10 - v00) * ax, v1 = v01 + (v11 - v01) * ax;
      h[k] = v0 + (v1 - v0) * ay;
    }
    return rejected;
  }
};

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
  std::vector<size_t> rejected_per_row(size_t(ny), 0);
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
    // Light change of three neighbouring columns (vertical maxima), rotated the same way.
    std::vector<float> change_max(light_change ? 3 * static_cast<size_t>(nz) : 0);
    for (int y = int(begin); y < int(end); ++y) {
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
        } else {
          const glm::vec3 d = view.directions[c];
          const glm::vec3 dv(glm::dot(d, hc.right), glm::dot(d, hc.up), glm::dot(d, hc.forward));
          projection->project(offset, dv, centers.data(), n, scratch.fx.data(), scratch.fy.data(),
                             scratch.fz.data(), scratch.inside.data());
          rejected = projection->read(scratch, cur, n, h.data());
        }
        rejected_per_row[size_t(y)] += rejected;
        const size_t len = size_t(n);
        if (clamp) {
          // Clamp the history to the range of the current frame's 3x3
          // neighbourhood in this slice (TAA-style): neighbours sample other
          // depth strata (column hash), so their range brackets the
          // converged value; history outside it is a ghost (moved shaft,
          // disocclusion) and is cut. HDRP does not clamp. Neighbours count
          // only where they are lit. The range is the columns' vertical
          // ranges combined across x - 1, x, x + 1 (clamped at the edges).
          if (x + 1 < nx) vertical_range(x + 1);  // into the slot x - 2 used
          const size_t left = size_t(std::max(x - 1, 0) % 3) * nz, mid = size_t(x % 3) * nz,
                       right = size_t(std::min(x + 1, nx - 1) % 3) * nz;
          const float* lo = range_lo.data();
          const float* hi = range_hi.data();
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
    }
  });
  for (size_t r : rejected_per_row) stats.rejected += r;
  return stats;
}

}  // namespace cr

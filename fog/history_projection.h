#pragma once
// The moving-camera history read of fog.reproject: froxel centres of the
// current view projected into the history's grid and read there with
// trilinear interpolation.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/core/fast_math.h"
#include "fog/froxel_passes.h"
#include "fog/sun_term_format.h"

namespace cr {

// Projection of a column's froxel centres into the history's grid, set up
// once per frame, for a history of values in format F (sun_term_format.h). A column's centres lie on one line, q(t) = offset + t dv in
// the history camera's frame (right, up, forward, relative to its position),
// so the projection runs as flat loops over the slices (the slice encoding's
// log is fast_log, which vectorises), then the trilinear reads per slice.
template <class F>
struct HistoryProjection {
  using Value = typename F::Value;
  const FroxelGrid* grid;
  const Value* values;
  // Per history column (x0, y0): the fewest slices the 2x2 columns x0..x1,
  // y0..y1 of a trilinear read from there hold (x1, y1 clamped to the grid).
  std::vector<uint16_t> lit_2x2;
  float scale_x, scale_y;  // pixels per unit of x/z and y/z
  float half_w, half_h;    // screen centre in pixels
  float max_px, max_py;    // grid extent in pixels
  float inv_size;          // 1 / froxel size

  HistoryProjection(const FroxelView& hv, const std::vector<Value>& history) {
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
  // corner the history culled). Returns how many slices had none. Floats
  // eight slices at a time where the CPU has AVX2 (read_avx2, the same bits).
  size_t read(const Scratch& s, const Value* cur, int n, Value* h) const;

  // read's definition, one slice at a time over slices [k0, n): lerps in z,
  // then x, then y, at the format's weights.
  size_t read_slices(const Scratch& s, const Value* cur, int k0, int n, Value* h) const {
    const FroxelGrid& hg = *grid;
    const int nx = hg.nx(), ny = hg.ny(), nz = hg.nz();
    size_t rejected = 0;
    for (int k = k0; k < n; ++k) {
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
      const typename F::Weight ax = F::weight(fx - float(x0)), ay = F::weight(fy - float(y0)),
                               az = F::weight(fz - float(z0));
      auto lerp_z = [&](int xi, int yi) {
        const Value* c = values + hg.index(xi, yi, z0);
        return F::lerp(c[0], c[dz], az);
      };
      const Value v00 = lerp_z(x0, y0), v10 = lerp_z(x1, y0), v01 = lerp_z(x0, y1), v11 = lerp_z(x1, y1);
      const Value v0 = F::lerp(v00, v10, ax), v1 = F::lerp(v01, v11, ax);
      h[k] = F::lerp(v0, v1, ay);
    }
    return rejected;
  }
};

template <>
size_t HistoryProjection<FloatSunTerm>::read(const Scratch& s, const float* cur, int n, float* h) const;
template <>
size_t HistoryProjection<Q15SunTerm>::read(const Scratch& s, const uint16_t* cur, int n, uint16_t* h) const;

}  // namespace cr

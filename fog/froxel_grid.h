#pragma once
// The camera-aligned froxel grid: nx x ny columns of froxel_size_px screen
// pixels, nz depth slices from the near plane to near + fog_distance.
// Depth is radial distance from the camera (a froxel edge is a sphere cap,
// as in HDRP), so slice thickness is the same for every column. Slices follow
// HDRP's generalised logarithmic encoding:
//   e(d) = log(1 + c (d - n)) / log(1 + c (f - n)),  c = max(2 - 2 u, 0.001)
// where u is the slice uniformity (0 = logarithmic, 1 = linear).
// Storage is column-major: index = (y * nx + x) * nz + z, so a column's
// slices are contiguous for the per-column passes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>


namespace cr {

class FroxelGrid {
 public:
  FroxelGrid() = default;
  FroxelGrid(int width, int height, int froxel_size_px, int slices, float near_dist, float fog_distance,
             float slice_uniformity);

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }
  int width() const { return width_; }
  int height() const { return height_; }
  int froxel_size() const { return size_px_; }
  size_t columns() const { return size_t(nx_) * ny_; }
  size_t count() const { return columns() * nz_; }
  size_t index(int x, int y, int z) const { return (size_t(y) * nx_ + x) * nz_ + z; }
  float near_distance() const { return near_; }
  float far_distance() const { return far_; }

  // Encoded depth in [0, 1] <-> radial distance in [near, far].
  float encode(float distance) const;
  float decode(float e) const;
  // Distance of slice boundary k in [0, nz] (0 = near, nz = far).
  float boundary(int k) const { return boundaries_[size_t(k)]; }
  // Slice centre in log space (HDRP: the stored value belongs there).
  float center(int k) const { return centers_[size_t(k)]; }
  float thickness(int k) const { return boundaries_[size_t(k) + 1] - boundaries_[size_t(k)]; }
  // Continuous slice coordinate of a distance (slice k spans [k, k+1)).
  // Float fast path of encode() (per froxel / per pixel).
  float slice_coord(float distance) const {
    const float d = std::min(std::max(distance, near_), far_);
    return std::log(1.0f + cf_ * (d - near_)) * slice_scale_;
  }

  // slice_coord's terms, for loops that take their own log:
  // slice_coord(d) = log(1 + log_c() (d - near)) * log_scale() for d in [near, far].
  float log_c() const { return cf_; }
  float log_scale() const { return slice_scale_; }

  // Slice containing a distance (clamped to [near, far]; far is in the last
  // slice), exact against boundary(): a table over distance gives a slice at
  // or below the answer and a few boundary compares finish it, no log.
  int slice_of(float distance) const {
    const float d = std::min(std::max(distance, near_), far_);
    const size_t cell = std::min(size_t((d - near_) * table_scale_), slice_table_.size() - 1);
    int k = slice_table_[cell];
    while (k + 1 < nz_ && d >= boundaries_[size_t(k) + 1]) ++k;
    return k;
  }

  // Screen pixel coordinate (continuous, pixel centres at +0.5) of a froxel column centre.
  glm::vec2 column_center_px(int x, int y) const;
  bool same_layout(const FroxelGrid& o) const;

 private:
  int width_ = 0, height_ = 0, size_px_ = 1;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  float near_ = 0.1f, far_ = 64.1f;
  double c_ = 1.0, log_range_ = 1.0;
  float cf_ = 1.0f, slice_scale_ = 1.0f;  // c and nz / log_range for slice_coord
  std::vector<float> boundaries_;
  std::vector<float> centers_;
  std::vector<uint16_t> slice_table_;  // per distance cell: a slice at or below the cell's first slice
  float table_scale_ = 1.0f;           // cells per metre
};

}  // namespace cr

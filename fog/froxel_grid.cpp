#include "fog/froxel_grid.h"

#include <algorithm>
#include <cmath>

namespace cr {

FroxelGrid::FroxelGrid(int width, int height, int froxel_size_px, int slices, float near_dist,
                       float fog_distance, float slice_uniformity)
    : width_(width), height_(height), size_px_(froxel_size_px) {
  nx_ = (width + froxel_size_px - 1) / froxel_size_px;
  ny_ = (height + froxel_size_px - 1) / froxel_size_px;
  nz_ = slices;
  near_ = near_dist;
  far_ = near_dist + fog_distance;
  // HDRP remaps uniformity [0, 1] -> c in [2, 0]; c > 0 keeps the log finite.
  c_ = std::max(2.0 - 2.0 * double(slice_uniformity), 0.001);
  log_range_ = std::log1p(c_ * double(far_ - near_));
  cf_ = float(c_);
  slice_scale_ = float(double(nz_) / log_range_);
  boundaries_.resize(size_t(nz_) + 1);
  centers_.resize(size_t(nz_));
  for (int k = 0; k <= nz_; ++k) boundaries_[size_t(k)] = decode(float(k) / float(nz_));
  boundaries_.front() = near_;
  boundaries_.back() = far_;
  for (int k = 0; k < nz_; ++k) centers_[size_t(k)] = decode((float(k) + 0.5f) / float(nz_));
  // 16 cells per slice on average; one slice lower than the cell start's, so
  // float rounding of the cell index can never put the start above a distance.
  const size_t cells = size_t(nz_) * 16;
  slice_table_.resize(cells);
  table_scale_ = float(double(cells) / double(far_ - near_));
  int k = 0;
  for (size_t i = 0; i < cells; ++i) {
    const float start = float(double(near_) + double(i) * double(far_ - near_) / double(cells));
    while (k + 1 < nz_ && start >= boundaries_[size_t(k) + 1]) ++k;
    slice_table_[i] = uint16_t(std::max(k - 1, 0));
  }
}

float FroxelGrid::encode(float distance) const {
  const double d = std::clamp(double(distance), double(near_), double(far_));
  return float(std::log1p(c_ * (d - near_)) / log_range_);
}

float FroxelGrid::decode(float e) const {
  const double x = std::clamp(double(e), 0.0, 1.0);
  return float(double(near_) + std::expm1(x * log_range_) / c_);
}

glm::vec2 FroxelGrid::column_center_px(int x, int y) const {
  return glm::vec2((float(x) + 0.5f) * float(size_px_), (float(y) + 0.5f) * float(size_px_));
}


bool FroxelGrid::same_layout(const FroxelGrid& o) const {
  return width_ == o.width_ && height_ == o.height_ && size_px_ == o.size_px_ && nz_ == o.nz_ &&
         near_ == o.near_ && far_ == o.far_ && c_ == o.c_;
}

}  // namespace cr

#pragma once
// Builds a SpecularEnvironment from a radiance function, in slices.
//
// Level 0 is the radiance at its texel centres (a mirror reflects it). Level
// k >= 1 is Karis' split-sum prefilter for GGX at alpha_k = r_k^2 with
// n = v = R: sum_i L(l_i) (n.l_i) / sum_i (n.l_i) over a fixed Hammersley
// set of half vectors, the same for every texel (turned into the texel's
// frame), so the result is deterministic. Filtered importance sampling
// (Krivanek & Colbert 2008): each sample reads a box-filtered pyramid of
// level 0 at the mip whose texel matches the solid angle the sample stands
// for, so few samples give a smooth result (no +1 mip bias: it blurred the
// rough levels by 3-9% against a brute-force convolution).
//
// Level k's size: its texel's angle, sqrt(4 pi) / size, about the lobe's
// half width alpha_k (power of two, at least 8, at most level 0's). Its
// sample count: `samples` times size_0 / size_k. A wide lobe needs more
// samples for the same error, and a coarse level has few texels, so each
// level costs about the same.
//
// Work is a list of items, done in order by any number of run() calls (a
// plugin spreads them over frames): level 0's rows first, then every
// prefiltered texel. Inside a call the items run as jobs writing disjoint
// texels, so the result is bit-identical for any thread count and any split
// into calls.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"
#include "engine/shading/specular_environment.h"

namespace cr {

class EnvironmentPrefilter {
 public:
  // Radiance arriving from n unit directions (dx, dy, dz)[i] into out[i]; called from several threads at once.
  using Radiance = std::function<void(size_t n, const float* dx, const float* dy, const float* dz, glm::vec3* out)>;

  // size: level 0's width, a power of two; levels >= 1; samples >= 1 (per texel of a level as large as level 0).
  EnvironmentPrefilter(int size, int levels, int samples);
  static std::vector<int> level_sizes(int size, int levels);

  size_t work_items() const { return size_t(size_) + prefiltered_texels_; }
  // First item of slice s of `slices` (s = slices: work_items()), splitting
  // the work by its cost (a radiance lookup or a pyramid sample each) rather
  // than by item count: a texel of a rough level takes more samples.
  size_t slice_begin(int s, int slices) const;
  bool complete() const { return done_ == work_items(); }
  // Items [begin, end); begin must be where the previous call ended (items run in order).
  void run(size_t begin, size_t end, const Radiance& radiance, JobSystem& jobs, const std::string& job_name);
  // The built environment (complete() only).
  std::shared_ptr<const SpecularEnvironment> result() const { return env_; }
  // Rounds the complete result to q15 (SpecularEnvironment::quantize_q15).
  void quantize_result_q15() { env_->quantize_q15(); }

 private:
  struct LevelSamples {
    size_t first_item = 0;      // of the level's first texel
    size_t texels = 0;
    std::vector<glm::vec4> l;   // n.l > 0 samples: local direction (n = +Z) and pyramid level
    float inv_weight_sum = 0.0f;
  };
  void base_row(int y, const Radiance& radiance);
  void build_pyramid();
  void prefilter_texel(size_t item);

  int size_;
  std::shared_ptr<SpecularEnvironment> env_;
  SpecularEnvironment pyramid_;  // level 0 box-filtered down to 1x1
  std::vector<LevelSamples> samples_;  // per level >= 1
  size_t prefiltered_texels_ = 0;
  uint64_t total_cost_ = 0;
  size_t done_ = 0;
};

// All items in one call.
std::shared_ptr<const SpecularEnvironment> prefilter_environment(int size, int levels, int samples,
                                                                 const EnvironmentPrefilter::Radiance& radiance,
                                                                 JobSystem& jobs);

}  // namespace cr

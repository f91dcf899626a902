#include "engine/output/percentile.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cr {

double percentile_nearest_rank(std::vector<double> samples, double p) {
  if (samples.empty()) return 0.0;
  p = std::clamp(p, 0.0, 100.0);
  std::sort(samples.begin(), samples.end());
  const double n = static_cast<double>(samples.size());
  // p/100*n in exact decimal terms can land a hair above an integer in binary
  // (0.95 * 100 = 95.00000000000001); round to 1e-9 before ceil so p95 of
  // 100 samples is rank 95, not 96.
  const double position = std::round(p / 100.0 * n * 1e9) / 1e9;
  const size_t rank = std::max<size_t>(1, static_cast<size_t>(std::ceil(position)));
  return samples[std::min(rank, samples.size()) - 1];
}

double median(std::vector<double> samples) { return percentile_nearest_rank(std::move(samples), 50.0); }

}  // namespace cr

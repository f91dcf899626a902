#pragma once
// Order statistics used by reports.
#include <vector>

namespace cr {

// Nearest-rank percentile: the smallest sample x such that at least p percent
// of the samples are <= x, i.e. the sorted sample at 1-based rank
// ceil(p/100 * n) (rank 1 for p = 0). No interpolation, so the result is
// always an observed value. Samples 1..100: p50 = 50, p95 = 95, p99 = 99.
// Returns 0 for an empty sample. p is clamped to [0, 100].
double percentile_nearest_rank(std::vector<double> samples, double p);

// The median as the nearest-rank p50: an observed value, for an even count
// the lower of the two middle samples. Returns 0 for an empty sample.
double median(std::vector<double> samples);

}  // namespace cr

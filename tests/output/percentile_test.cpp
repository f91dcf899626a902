#include <doctest/doctest.h>

#include "engine/output/percentile.h"

TEST_CASE("median: the nearest-rank p50, an observed sample (the lower middle one for an even count)") {
  CHECK(cr::median({3.0, 1.0, 2.0}) == 2.0);
  CHECK(cr::median({4.0, 1.0, 3.0, 2.0}) == 2.0);
  CHECK(cr::median({7.0}) == 7.0);
  CHECK(cr::median({}) == 0.0);
  const std::vector<double> v = {5.0, 9.0, 1.0, 3.0, 8.0, 2.0};
  CHECK(cr::median(v) == cr::percentile_nearest_rank(v, 50));
}

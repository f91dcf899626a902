#include <cmath>
#include <random>

#include <doctest/doctest.h>

#include "atmosphere/tools/reference_merge.h"
#include "engine/core/error.h"

using namespace cr;

namespace {

// A noisy estimate of `truth` from `paths` samples of unit-variance noise per pixel.
ReferenceLuminance noisy(const std::vector<float>& truth, int paths, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  ReferenceLuminance r;
  const float sigma = 1.0f / std::sqrt(float(paths));
  for (float t : truth) {
    r.luminance.push_back(t + sigma * gauss(rng));
    r.noise.push_back(sigma);
  }
  return r;
}

double rms_error(const std::vector<float>& a, const std::vector<float>& truth) {
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) s += (a[i] - truth[i]) * double(a[i] - truth[i]);
  return std::sqrt(s / double(a.size()));
}

}  // namespace

TEST_CASE("reference merge: weights by path count, so the merged noise is that of the pooled paths") {
  std::vector<float> truth(20000);
  for (size_t i = 0; i < truth.size(); ++i) truth[i] = 10.0f + float(i % 97);
  const ReferenceLuminance a = noisy(truth, 1, 1), b = noisy(truth, 3, 2);
  const ReferenceLuminance m = merge_references({a, b}, "test");
  // 1 + 3 paths: standard error 1/2, stated and measured.
  CHECK(m.noise[0] == doctest::Approx(0.5).epsilon(1e-5));
  CHECK(rms_error(m.luminance, truth) == doctest::Approx(0.5).epsilon(0.03));
  // An equal-weight average would be worse: sqrt(1 + 1/3) / 2 = 0.577.
  CHECK(rms_error(a.luminance, truth) == doctest::Approx(1.0).epsilon(0.03));
  // One reference is returned as it is.
  CHECK(merge_references({a}, "test").luminance == a.luminance);
}

TEST_CASE("reference merge: the same image twice, different sizes, or nothing are clear errors") {
  const std::vector<float> truth(100, 5.0f);
  const ReferenceLuminance a = noisy(truth, 4, 7);
  CHECK_THROWS_WITH_AS(merge_references({a, a}, "sun95.exr"), doctest::Contains("same image"), InputError);
  ReferenceLuminance small = noisy(std::vector<float>(50, 5.0f), 4, 8);
  CHECK_THROWS_WITH_AS(merge_references({a, small}, "sun95.exr"), doctest::Contains("different sizes"), InputError);
  CHECK_THROWS_AS(merge_references({}, "sun95.exr"), InputError);
}

TEST_CASE("reference merge: colour-ratio noise merges like the luminance noise, and only when every reference has it") {
  std::vector<float> truth(100, 5.0f);
  ReferenceLuminance a = noisy(truth, 1, 1), b = noisy(truth, 3, 2);
  a.ratio_noise.assign(2 * truth.size(), 0.2f);
  b.ratio_noise.assign(2 * truth.size(), 0.1f);
  const ReferenceLuminance m = merge_references({a, b}, "test");
  // Weights 1/4 and 3/4 (by path count): sqrt((0.25 * 0.2)^2 + (0.75 * 0.1)^2).
  REQUIRE(m.ratio_noise.size() == 2 * truth.size());
  CHECK(m.ratio_noise[0] == doctest::Approx(std::sqrt(0.05 * 0.05 + 0.075 * 0.075)).epsilon(1e-5));
  b.ratio_noise.clear();
  CHECK(merge_references({a, b}, "test").ratio_noise.empty());
  b.ratio_noise.assign(3, 0.1f);
  CHECK_THROWS_AS(merge_references({a, b}, "test"), InputError);
}

#include <cmath>

#include <doctest/doctest.h>

#include "atmosphere/tools/accuracy_score.h"

using namespace cr;

TEST_CASE("accuracy score: dark pixels are counted apart, noise explains its share of the error") {
  // 99 bright pixels with a 2% error and 2% noise, one pixel far below 1% of the mean.
  std::vector<float> ref(100, 100.0f), lut(100, 102.0f), noise(100, 2.0f);
  ref[0] = 1e-6f;
  lut[0] = 0.5f;
  const AccuracyScore s = score_accuracy(lut, ref, noise, {});
  CHECK(s.considered == 100);
  CHECK(s.dark == 1);
  CHECK(s.scored == 99);
  CHECK(s.mean == doctest::Approx(0.02));
  CHECK(s.p95 == doctest::Approx(0.02));
  CHECK(s.dark_error == doctest::Approx(0.5 / (99 * 100.0 / 100)).epsilon(0.01));
  CHECK(s.noise_mean == doctest::Approx(0.02));
  CHECK(s.bias_rms == doctest::Approx(0.0).epsilon(1e-6));
  CHECK(s.within_noise);
  // Four times the error with the same noise: mostly bias.
  std::vector<float> biased(100, 108.0f);
  const AccuracyScore b = score_accuracy(biased, ref, noise, {});
  CHECK(b.mean == doctest::Approx(0.08));
  CHECK(b.bias_rms == doctest::Approx(std::sqrt(0.08 * 0.08 - 0.02 * 0.02)));
  CHECK_FALSE(b.within_noise);
  // The mask restricts the considered pixels; an all-black reference scores nothing.
  std::vector<bool> mask(100, false);
  mask[5] = true;
  CHECK(score_accuracy(lut, ref, noise, mask).considered == 1);
  const AccuracyScore black = score_accuracy(lut, std::vector<float>(100, 0.0f), noise, {});
  CHECK(black.scored == 0);
  CHECK(black.dark == 100);
}

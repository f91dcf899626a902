#include "atmosphere/tools/accuracy_score.h"

#include <algorithm>
#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/output/percentile.h"

namespace cr {

AccuracyScore score_accuracy(const std::vector<float>& lut_luminance, const std::vector<float>& ref_luminance,
                             const std::vector<float>& ref_noise, const std::vector<bool>& mask,
                             double dark_fraction) {
  AccuracyScore s;
  const size_t n = ref_luminance.size();
  auto considered = [&](size_t i) { return mask.empty() || mask[i]; };
  double ref_sum = 0.0;
  for (size_t i = 0; i < n; ++i)
    if (considered(i)) {
      ref_sum += ref_luminance[i];
      ++s.considered;
    }
  if (s.considered == 0) return s;
  const double ref_mean = ref_sum / double(s.considered);
  s.floor = dark_fraction * ref_mean;
  std::vector<double> errors, noise;
  double sq = 0.0, noise_sq = 0.0, dark_abs = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (!considered(i)) continue;
    const double yr = ref_luminance[i], yt = lut_luminance[i];
    // A floor of 0 (an all-black reference) leaves every pixel dark: relative error has no meaning there.
    if (!(yr >= s.floor) || !(yr > 0.0)) {
      ++s.dark;
      dark_abs += std::abs(yt - yr);
      continue;
    }
    const double e = std::abs(yt - yr) / yr;
    const double sigma = ref_noise.empty() ? 0.0 : double(ref_noise[i]) / yr;
    errors.push_back(e);
    noise.push_back(sigma);
    sq += e * e;
    noise_sq += sigma * sigma;
  }
  s.scored = errors.size();
  if (s.dark > 0) s.dark_error = ref_mean > 0.0 ? dark_abs / double(s.dark) / ref_mean : 0.0;
  if (errors.empty()) return s;
  const double count = double(errors.size());
  for (size_t k = 0; k < errors.size(); ++k) {
    s.mean += errors[k];
    s.noise_mean += noise[k];
  }
  s.mean /= count;
  s.noise_mean /= count;
  s.p95 = percentile_nearest_rank(errors, 95.0);
  s.noise_p95 = percentile_nearest_rank(noise, 95.0);
  s.noise_expected = std::sqrt(2.0 / kPiD) * s.noise_mean;
  s.rms = std::sqrt(sq / count);
  s.noise_rms = std::sqrt(noise_sq / count);
  s.bias_rms = std::sqrt(std::max(0.0, s.rms * s.rms - s.noise_rms * s.noise_rms));
  s.within_noise = s.rms <= kWithinNoise * s.noise_rms;
  return s;
}

}  // namespace cr

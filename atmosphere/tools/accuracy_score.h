#pragma once
// The error of a LUT render against the path-traced reference, per pixel luminance:
//  - relative error |Y_lut - Y_ref| / Y_ref, mean and p95, over the scored pixels;
//  - pixels whose reference luminance is below a floor (a fraction of the mean
//    reference luminance of the considered pixels: night, the earth's shadow,
//    the dark side seen from space) are not scored by relative error, which is
//    meaningless near 0; they are counted and their absolute error is reported
//    relative to that mean luminance instead;
//  - the reference's own Monte-Carlo noise (per-pixel standard error) over the
//    same pixels, and the share of the error it explains: for pixel i the
//    squared error is bias_i^2 + sigma_i^2 in expectation, so the RMS bias is
//    sqrt(mean(e^2) - mean(sigma^2)).
#include <cstddef>
#include <vector>

namespace cr {

struct AccuracyScore {
  size_t considered = 0;      // pixels in the mask
  size_t scored = 0;          // of those, reference luminance >= floor
  size_t dark = 0;            // of those, below the floor
  double floor = 0.0;         // the luminance floor (cd/m^2)
  double mean = 0.0;          // mean relative error over the scored pixels
  double p95 = 0.0;           // 95th percentile (nearest rank) of the same
  double dark_error = 0.0;    // mean |Y_lut - Y_ref| of the dark pixels / mean Y_ref of the considered pixels
  double noise_mean = 0.0;    // mean relative standard error of the reference over the scored pixels
  double noise_p95 = 0.0;     // its 95th percentile
  double noise_expected = 0.0;  // mean relative error that the reference noise alone would give: sqrt(2/pi) * noise_mean
  double rms = 0.0;           // RMS relative error over the scored pixels
  double noise_rms = 0.0;     // RMS relative standard error
  double bias_rms = 0.0;      // sqrt(max(0, rms^2 - noise_rms^2)): the error not explained by the noise
  // The measured error is within the reference noise: rms <= kWithinNoise * noise_rms.
  bool within_noise = false;
};

inline constexpr double kDarkFraction = 0.01;  // floor = 1% of the mean reference luminance
inline constexpr double kWithinNoise = 1.2;

// All vectors have one value per pixel; `mask` empty = every pixel considered.
// `ref_noise` = standard error of the reference luminance (0 where exact).
AccuracyScore score_accuracy(const std::vector<float>& lut_luminance, const std::vector<float>& ref_luminance,
                             const std::vector<float>& ref_noise, const std::vector<bool>& mask,
                             double dark_fraction = kDarkFraction);

}  // namespace cr

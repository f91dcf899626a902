#pragma once
// Several path-traced references of one view (rendered with different seeds)
// combined into one with less noise. Each reference k has per-pixel luminance
// Y_k and standard error s_k. Each image gets one weight, w_k = 1 / mean(s_k^2),
// which is proportional to its path count: a per-pixel inverse-variance weight
// would be biased, since a pixel's noise estimate is correlated with its value.
//   Y = sum w_k Y_k / sum w_k,   s = sqrt(sum w_k^2 s_k^2) / sum w_k.
#include <string>
#include <vector>

namespace cr {

struct ReferenceLuminance {
  std::vector<float> luminance;
  std::vector<float> noise;  // standard error of the luminance, per pixel
  std::vector<float> color;  // linear R, G, B per pixel (interleaved), or empty; merged by the same weights
  // Relative standard errors of r/g and b/g per pixel (interleaved), or empty; merged like the noise.
  std::vector<float> ratio_noise;
};

// The colours (and ratio noises) are merged when every reference has them (else the result has none).
// Throws InputError (naming `what`) when the sizes differ or two references
// are the same image (rendered with the same seed: no independent samples).
ReferenceLuminance merge_references(const std::vector<ReferenceLuminance>& refs, const std::string& what);

}  // namespace cr

#pragma once
// LDR-FLIP, the perceptual image difference of Andersson et al. 2020,
// "FLIP: A Difference Evaluator for Alternating Images" (HPG 2020),
// implemented from the paper:
//   colour: linear RGB -> YCxCz, per-channel contrast sensitivity filtering
//   (Gaussian CSFs at the observer's pixels per degree), clamp to the RGB
//   cube, Hunt-adjusted L*a*b*, HyAB distance, exponent qc = 0.7, and the
//   error redistribution to [0,1] with cmax (green-blue distance), pc = 0.4,
//   pt = 0.95;
//   features: edges and points of the achromatic channel via first and
//   second Gaussian derivatives (sigma = 0.5 * 0.082 deg), exponent qf = 0.5;
//   per pixel: dE = dEc ^ (1 - dEf), in [0,1] (0 = identical).
#include <vector>

#include "engine/core/math_constants.h"
#include "engine/output/image.h"

namespace cr {

// 0.7 m viewing distance, 0.7 m wide monitor of 3840 pixels (the paper's default).
constexpr double kFlipDefaultPixelsPerDegree = 0.7 * (3840.0 / 0.7) * kPiD / 180.0;

// Per-pixel FLIP error (row-major) between two same-size images of linear
// RGB values; values are clamped to [0,1] first (for display-encoded inputs
// apply srgb_to_linear; for HDR tonemap first). Throws cr::Error on a size
// mismatch.
std::vector<float> flip_error_map(const ImageRGBf& reference_linear, const ImageRGBf& test_linear,
                                  double pixels_per_degree = kFlipDefaultPixelsPerDegree);

// Mean of an error map, summed in index order (deterministic).
double mean_error(const std::vector<float>& error_map);

}  // namespace cr

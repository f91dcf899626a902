#pragma once
// Image comparison for golden-image tests: pixel metrics, a perceptual
// metric (LDR-FLIP, see flip.h), thresholds and a pass/fail verdict.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/output/flip.h"
#include "engine/output/image.h"

namespace cr {

enum class ImageEncoding {
  Display,  // sRGB-encoded values in [0,1] (8-bit PNG / 255)
  Linear,   // scene-linear radiance, unbounded (EXR)
};

// A metric fails when it exceeds its threshold (strictly); NaN always fails.
// Defaults suit 8-bit renders that should be the same up to last-bit
// differences between compilers and machines:
struct CompareThresholds {
  double max_abs = 0.1;                  // largest channel difference (a stray pixel may differ)
  double rmse = 0.01;                    // about 2.5 codes of 8-bit noise everywhere
  double pixel_threshold = 2.0 / 255.0;  // a pixel "differs" above this (ignores 1-code rounding)
  double max_fraction = 0.001;           // at most 0.1% of pixels may differ
  double flip_mean = 0.05;               // a uniform 1-code change costs 0.02-0.04
};

struct CompareMetrics {
  int width = 0;
  int height = 0;
  ImageEncoding encoding = ImageEncoding::Display;
  std::array<double, 3> max_abs_channel{};  // per channel R, G, B
  double max_abs = 0.0;                     // max over channels
  double rmse = 0.0;                        // over all channel values
  double psnr_db = 0.0;                     // 20 log10(1 / rmse), peak 1.0; +inf when identical
  size_t pixels_over = 0;                   // pixels whose max channel difference > pixel_threshold
  double fraction_over = 0.0;
  double flip_mean = 0.0;
  std::string flip_method;                  // how the FLIP inputs were prepared
  // Relative luminance error |Y_test - Y_ref| / Y_ref on linear values (PNG
  // inputs sRGB-decoded), pixels whose reference is darker than 1% of the
  // mean reference luminance measured against that floor; mean and
  // nearest-rank p95. Reported, not thresholded.
  double rel_luminance_mean = 0.0;
  double rel_luminance_p95 = 0.0;
};

struct CompareResult {
  CompareMetrics metrics;
  std::vector<float> flip_map;     // per-pixel FLIP error in [0,1]
  std::vector<float> difference;   // per-pixel max channel |difference|
  bool pass = true;
  std::vector<std::string> failures;  // one line per failed threshold
};

// Compares two same-size images (reference first). Differences involving
// NaN count as +inf. For Linear images the pixel metrics use linear values
// and FLIP compares after a fixed exposure of 0 EV and the ACES filmic
// tonemap (Narkowicz fit, as in HDR-FLIP). Throws cr::Error on size mismatch.
CompareResult compare_images(const ImageRGBf& reference, const ImageRGBf& test,
                             ImageEncoding encoding, const CompareThresholds& thresholds,
                             double pixels_per_degree = kFlipDefaultPixelsPerDegree);

// Loads two PNG or two EXR files (detected by content) and compares them.
// Throws cr::InputError naming the offending file for unreadable, empty,
// non-image or mismatched-format files and for different sizes.
CompareResult compare_image_files(const std::string& reference_path, const std::string& test_path,
                                  const CompareThresholds& thresholds,
                                  double pixels_per_degree = kFlipDefaultPixelsPerDegree);

enum class HeatmapKind {
  Flip,        // per-pixel FLIP error, 0..1
  Difference,  // max channel |difference|, scaled so the largest one is brightest
};

// Writes the chosen per-pixel error as a magma-coloured RGB PNG, atomically.
void write_error_heatmap(const std::string& path, const CompareResult& result,
                         HeatmapKind kind = HeatmapKind::Flip);

// ACES filmic tonemap at exposure 0 (HDR-FLIP's constants), output in [0,1].
float tonemap_aces(float linear);

nlohmann::json compare_result_to_json(const CompareResult& result,
                                      const CompareThresholds& thresholds);
// The inverses for its "metrics" (width, height and encoding are not in it)
// and "thresholds" objects; nlohmann::json::exception on a missing or
// mistyped field.
CompareMetrics compare_metrics_from_json(const nlohmann::json& metrics);
CompareThresholds compare_thresholds_from_json(const nlohmann::json& thresholds);
// A readable table: each metric, its threshold and whether it passed.
std::string format_compare_result(const CompareResult& result, const CompareThresholds& thresholds);
// PSNR as text: "inf" for identical images.
std::string format_psnr(double psnr_db);

}  // namespace cr

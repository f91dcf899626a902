#include "engine/output/image_compare.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/luminance.h"
#include "engine/output/color_map.h"
#include "engine/output/exr_io.h"
#include "engine/output/percentile.h"
#include "engine/output/png_io.h"
#include "engine/core/srgb.h"

namespace cr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class FileFormat { Png, Exr };

FileFormat detect_format(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError(path, "is a directory, not an image");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open image: ") + std::strerror(errno));
  unsigned char magic[8] = {};
  in.read(reinterpret_cast<char*>(magic), sizeof magic);
  const std::streamsize got = in.gcount();
  if (got == 0) throw InputError(path, "empty file, not an image");
  static constexpr unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static constexpr unsigned char exr[4] = {0x76, 0x2f, 0x31, 0x01};
  if (got >= 8 && std::memcmp(magic, png, 8) == 0) return FileFormat::Png;
  if (got >= 4 && std::memcmp(magic, exr, 4) == 0) return FileFormat::Exr;
  throw InputError(path, "not a PNG or EXR image (unrecognised file signature)");
}

const char* format_name(FileFormat format) { return format == FileFormat::Png ? "PNG" : "EXR"; }

// |a - b| with equal values (including equal infinities) giving 0 and any
// NaN involvement giving +inf, so a broken pixel can never pass.
double channel_difference(float a, float b) {
  if (a == b) return 0.0;
  const double d = std::abs(static_cast<double>(a) - static_cast<double>(b));
  return std::isnan(d) ? kInf : d;
}

ImageRGBf flip_input(const ImageRGBf& image, ImageEncoding encoding) {
  ImageRGBf out = image;
  for (float& v : out.rgb) {
    v = encoding == ImageEncoding::Display ? srgb_to_linear(std::clamp(v, 0.0f, 1.0f))
                                           : tonemap_aces(v);
  }
  return out;
}

bool exceeds(double value, double threshold) { return !(value <= threshold); }

std::string number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

nlohmann::json json_number(double value) {
  if (std::isfinite(value)) return value;
  return std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
}

// CompareMetrics::rel_luminance_mean and _p95.
void relative_luminance_error(const ImageRGBf& reference, const ImageRGBf& test, ImageEncoding encoding,
                              CompareMetrics& m) {
  const size_t pixels = reference.pixel_count();
  if (pixels == 0) return;
  auto y_of = [&](const ImageRGBf& img, size_t i) {
    glm::dvec3 c(img.rgb[i * 3], img.rgb[i * 3 + 1], img.rgb[i * 3 + 2]);
    if (encoding == ImageEncoding::Display)
      for (int k = 0; k < 3; ++k) c[k] = srgb_to_linear(float(c[k]));
    return luminance(c);
  };
  std::vector<double> y_ref(pixels), errors(pixels);
  double mean_ref = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    y_ref[i] = y_of(reference, i);
    mean_ref += y_ref[i] / double(pixels);
  }
  const double floor = std::max(0.01 * mean_ref, 1e-30);
  double sum = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    const double e = std::abs(y_of(test, i) - y_ref[i]) / std::max(y_ref[i], floor);
    errors[i] = std::isnan(e) ? kInf : e;
    sum += errors[i];
  }
  m.rel_luminance_mean = sum / double(pixels);
  m.rel_luminance_p95 = percentile_nearest_rank(std::move(errors), 95.0);
}

}  // namespace

float tonemap_aces(float linear) {
  // Narkowicz 2016 ACES fit with its 0.6 pre-exposure folded into the
  // coefficients, exactly as HDR-FLIP applies it at exposure 0.
  constexpr double k0 = 0.6 * 0.6 * 2.51, k1 = 0.6 * 0.03;
  constexpr double k3 = 0.6 * 0.6 * 2.43, k4 = 0.6 * 0.59, k5 = 0.14;
  if (std::isnan(linear)) return 0.0f;
  const double x = std::max(0.0, static_cast<double>(linear));
  if (std::isinf(x)) return 1.0f;
  const double y = (k0 * x * x + k1 * x) / (k3 * x * x + k4 * x + k5);
  return static_cast<float>(std::clamp(y, 0.0, 1.0));
}

CompareResult compare_images(const ImageRGBf& reference, const ImageRGBf& test,
                             ImageEncoding encoding, const CompareThresholds& thresholds,
                             double pixels_per_degree) {
  if (reference.width != test.width || reference.height != test.height)
    throw Error("image sizes differ: " + std::to_string(reference.width) + "x" +
                std::to_string(reference.height) + " vs " + std::to_string(test.width) + "x" +
                std::to_string(test.height));
  CompareResult result;
  CompareMetrics& m = result.metrics;
  m.width = reference.width;
  m.height = reference.height;
  m.encoding = encoding;
  const size_t pixels = reference.pixel_count();
  result.difference.resize(pixels);
  double squared_sum = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    double pixel_max = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double d = channel_difference(reference.rgb[i * 3 + c], test.rgb[i * 3 + c]);
      m.max_abs_channel[c] = std::max(m.max_abs_channel[c], d);
      pixel_max = std::max(pixel_max, d);
      squared_sum += d * d;
    }
    result.difference[i] = static_cast<float>(pixel_max);
    if (pixel_max > thresholds.pixel_threshold) ++m.pixels_over;
  }
  m.max_abs = std::max({m.max_abs_channel[0], m.max_abs_channel[1], m.max_abs_channel[2]});
  m.rmse = pixels > 0 ? std::sqrt(squared_sum / static_cast<double>(pixels * 3)) : 0.0;
  m.psnr_db = m.rmse == 0.0 ? kInf : 20.0 * std::log10(1.0 / m.rmse);
  m.fraction_over = pixels > 0 ? static_cast<double>(m.pixels_over) / static_cast<double>(pixels) : 0.0;

  relative_luminance_error(reference, test, encoding, m);

  result.flip_map = flip_error_map(flip_input(reference, encoding), flip_input(test, encoding),
                                   pixels_per_degree);
  m.flip_mean = mean_error(result.flip_map);
  char method[160];
  std::snprintf(method, sizeof method, "LDR-FLIP at %.1f pixels/degree, %s", pixels_per_degree,
                encoding == ImageEncoding::Display
                    ? "sRGB inputs"
                    : "HDR inputs at exposure 0 EV through the ACES tonemap (Narkowicz fit)");
  m.flip_method = method;

  auto check = [&](const char* what, double value, double threshold) {
    if (exceeds(value, threshold))
      result.failures.push_back(std::string(what) + " " + number(value) + " > threshold " +
                                number(threshold));
  };
  check("max abs difference", m.max_abs, thresholds.max_abs);
  check("RMSE", m.rmse, thresholds.rmse);
  check("fraction of differing pixels", m.fraction_over, thresholds.max_fraction);
  check("mean FLIP", m.flip_mean, thresholds.flip_mean);
  result.pass = result.failures.empty();
  return result;
}

CompareResult compare_image_files(const std::string& reference_path, const std::string& test_path,
                                  const CompareThresholds& thresholds, double pixels_per_degree) {
  const FileFormat reference_format = detect_format(reference_path);
  const FileFormat test_format = detect_format(test_path);
  if (reference_format != test_format)
    throw InputError(test_path, std::string("is ") + format_name(test_format) +
                                    " but the reference " + reference_path + " is " +
                                    format_name(reference_format) + "; compare like with like");
  ImageRGBf reference, test;
  ImageEncoding encoding;
  if (reference_format == FileFormat::Png) {
    reference = read_png_rgb(reference_path);
    test = read_png_rgb(test_path);
    encoding = ImageEncoding::Display;
  } else {
    reference = read_exr(reference_path).color;
    test = read_exr(test_path).color;
    encoding = ImageEncoding::Linear;
  }
  if (reference.width != test.width || reference.height != test.height)
    throw InputError(test_path, "size " + std::to_string(test.width) + "x" +
                                    std::to_string(test.height) + " differs from the reference " +
                                    reference_path + " (" + std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height) + ")");
  return compare_images(reference, test, encoding, thresholds, pixels_per_degree);
}

void write_error_heatmap(const std::string& path, const CompareResult& result, HeatmapKind kind) {
  const CompareMetrics& m = result.metrics;
  if (kind == HeatmapKind::Flip) {
    write_png(path, heatmap_rgb8(result.flip_map, m.width, m.height, 1.0f));
    return;
  }
  // An infinite (NaN-involved) difference would make every finite one black:
  // scale by the largest finite difference and show infinite ones at full scale.
  float scale = 0.0f;
  for (float d : result.difference)
    if (std::isfinite(d)) scale = std::max(scale, d);
  write_png(path, heatmap_rgb8(result.difference, m.width, m.height, scale > 0.0f ? scale : 1.0f));
}

nlohmann::json compare_result_to_json(const CompareResult& result,
                                      const CompareThresholds& thresholds) {
  const CompareMetrics& m = result.metrics;
  return {
      {"pass", result.pass},
      {"failures", result.failures},
      {"width", m.width},
      {"height", m.height},
      {"encoding", m.encoding == ImageEncoding::Display ? "display (sRGB)" : "linear (HDR)"},
      {"metrics",
       {{"max_abs", json_number(m.max_abs)},
        {"max_abs_rgb",
         {json_number(m.max_abs_channel[0]), json_number(m.max_abs_channel[1]),
          json_number(m.max_abs_channel[2])}},
        {"rmse", json_number(m.rmse)},
        {"psnr_db", json_number(m.psnr_db)},
        {"pixels_over_threshold", m.pixels_over},
        {"fraction_over_threshold", m.fraction_over},
        {"flip_mean", m.flip_mean},
        {"rel_luminance_mean", json_number(m.rel_luminance_mean)},
        {"rel_luminance_p95", json_number(m.rel_luminance_p95)},
        {"flip_method", m.flip_method}}},
      {"thresholds",
       {{"max_abs", json_number(thresholds.max_abs)},
        {"rmse", json_number(thresholds.rmse)},
        {"pixel_threshold", json_number(thresholds.pixel_threshold)},
        {"max_fraction", json_number(thresholds.max_fraction)},
        {"flip_mean", json_number(thresholds.flip_mean)}}},
  };
}

namespace {

// json_number's inverse.
double number_from_json(const nlohmann::json& v) {
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  }
  return v.get<double>();
}

}  // namespace

CompareMetrics compare_metrics_from_json(const nlohmann::json& j) {
  CompareMetrics m;
  m.max_abs = number_from_json(j.at("max_abs"));
  for (int c = 0; c < 3; ++c) m.max_abs_channel[size_t(c)] = number_from_json(j.at("max_abs_rgb").at(size_t(c)));
  m.rmse = number_from_json(j.at("rmse"));
  m.psnr_db = number_from_json(j.at("psnr_db"));
  m.pixels_over = j.at("pixels_over_threshold").get<size_t>();
  m.fraction_over = j.at("fraction_over_threshold").get<double>();
  m.flip_mean = j.at("flip_mean").get<double>();
  m.rel_luminance_mean = number_from_json(j.at("rel_luminance_mean"));
  m.rel_luminance_p95 = number_from_json(j.at("rel_luminance_p95"));
  m.flip_method = j.at("flip_method").get<std::string>();
  return m;
}

CompareThresholds compare_thresholds_from_json(const nlohmann::json& j) {
  CompareThresholds t;
  t.max_abs = number_from_json(j.at("max_abs"));
  t.rmse = number_from_json(j.at("rmse"));
  t.pixel_threshold = number_from_json(j.at("pixel_threshold"));
  t.max_fraction = number_from_json(j.at("max_fraction"));
  t.flip_mean = number_from_json(j.at("flip_mean"));
  return t;
}

std::string format_psnr(double psnr_db) { return number(psnr_db); }

std::string format_compare_result(const CompareResult& result, const CompareThresholds& thresholds) {
  const CompareMetrics& m = result.metrics;
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%dx%d, %s values\n", m.width, m.height,
                m.encoding == ImageEncoding::Display ? "display (sRGB)" : "linear (HDR)");
  out += line;
  auto row = [&](const char* name, const std::string& value, const std::string& limit, bool ok) {
    std::snprintf(line, sizeof line, "  %-26s %14s  %14s  %s\n", name, value.c_str(),
                  limit.c_str(), ok ? "ok" : "FAIL");
    out += line;
  };
  std::snprintf(line, sizeof line, "  %-26s %14s  %14s\n", "metric", "value", "threshold");
  out += line;
  row("max abs difference", number(m.max_abs), number(thresholds.max_abs),
      !exceeds(m.max_abs, thresholds.max_abs));
  std::snprintf(line, sizeof line, "    per channel R G B        %s %s %s\n",
                number(m.max_abs_channel[0]).c_str(), number(m.max_abs_channel[1]).c_str(),
                number(m.max_abs_channel[2]).c_str());
  out += line;
  row("RMSE", number(m.rmse), number(thresholds.rmse), !exceeds(m.rmse, thresholds.rmse));
  std::snprintf(line, sizeof line, "  %-26s %14s\n", "PSNR (dB, peak 1.0)", number(m.psnr_db).c_str());
  out += line;
  const std::string fraction_name = "pixels > " + number(thresholds.pixel_threshold);
  row(fraction_name.c_str(), number(m.fraction_over) + " (" + std::to_string(m.pixels_over) + ")",
      number(thresholds.max_fraction), !exceeds(m.fraction_over, thresholds.max_fraction));
  row("mean FLIP", number(m.flip_mean), number(thresholds.flip_mean),
      !exceeds(m.flip_mean, thresholds.flip_mean));
  out += "  (" + m.flip_method + ")\n";
  std::snprintf(line, sizeof line, "  %-26s %14s\n", "rel. luminance error mean", number(m.rel_luminance_mean).c_str());
  out += line;
  std::snprintf(line, sizeof line, "  %-26s %14s\n", "rel. luminance error p95", number(m.rel_luminance_p95).c_str());
  out += line;
  out += result.pass ? "PASS\n" : "FAIL\n";
  return out;
}

}  // namespace cr

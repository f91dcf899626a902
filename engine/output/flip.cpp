#include "engine/output/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "engine/core/error.h"

namespace cr {
namespace {

using Plane = std::vector<float>;
using Vec3 = std::array<double, 3>;

// sRGB primaries, D65 white (IEC 61966-2-1), as exact ratios.
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
constexpr double kXyzToRgb[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                                    {-0.969224334, 1.875930071, 0.041554224},
                                    {0.055639423, -0.204011202, 1.057148933}};

// FLIP's parameters (paper, Sections 3 and 4).
constexpr double kQc = 0.7;    // colour difference exponent
constexpr double kQf = 0.5;    // feature difference exponent
constexpr double kPc = 0.4;    // redistribution: fraction of cmax mapped to ...
constexpr double kPt = 0.95;   // ... this fraction of the error range
constexpr double kFeatureWidth = 0.082;  // degrees, peak-to-trough of the edge detector

// Contrast sensitivity functions as sums of two Gaussians, S(x) =
// a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
// x in degrees; achromatic, red-green and blue-yellow channels.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfMaxB = 0.04;  // widest Gaussian: sets the common filter radius

Vec3 multiply(const double m[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

const Vec3& white_xyz() {
  static const Vec3 white = multiply(kRgbToXyz, {1.0, 1.0, 1.0});
  return white;
}

// YCxCz: the linearised (no cube root) opponent space of CIELAB.
Vec3 xyz_to_ycxcz(const Vec3& xyz) {
  const Vec3& w = white_xyz();
  const double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxcz_to_xyz(const Vec3& ycc) {
  const Vec3& w = white_xyz();
  const double y = (ycc[0] + 16.0) / 116.0;
  return {(y + ycc[1] / 500.0) * w[0], y * w[1], (y - ycc[2] / 200.0) * w[2]};
}

Vec3 xyz_to_hunt_lab(const Vec3& xyz) {
  const Vec3& w = white_xyz();
  constexpr double delta = 6.0 / 29.0;
  auto f = [&](double t) {
    return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / w[0]), fy = f(xyz[1] / w[1]), fz = f(xyz[2] / w[2]);
  const double l = 116.0 * fy - 16.0;
  // Hunt effect: chroma appears lower at low luminance.
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Vec3& a, const Vec3& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

// 1D correlation along x then along y with clamp-to-edge borders. Rows are
// padded once and the vertical pass accumulates whole rows, so the inner
// loops are branch-free and walk memory contiguously.
Plane filter_separable(const Plane& in, int width, int height, const std::vector<double>& kx,
                       const std::vector<double>& ky) {
  const int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
  const size_t w = static_cast<size_t>(width);
  Plane horizontal(in.size()), out(in.size());
  std::vector<double> padded(w + 2 * static_cast<size_t>(rx));
  for (int y = 0; y < height; ++y) {
    const float* row = in.data() + static_cast<size_t>(y) * w;
    for (size_t i = 0; i < padded.size(); ++i)
      padded[i] = row[std::clamp(static_cast<int>(i) - rx, 0, width - 1)];
    float* dst = horizontal.data() + static_cast<size_t>(y) * w;
    for (size_t x = 0; x < w; ++x) {
      double sum = 0.0;
      for (size_t k = 0; k < kx.size(); ++k) sum += kx[k] * padded[x + k];
      dst[x] = static_cast<float>(sum);
    }
  }
  std::vector<double> sum(w);
  for (int y = 0; y < height; ++y) {
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int k = -ry; k <= ry; ++k) {
      const float* src = horizontal.data() + static_cast<size_t>(std::clamp(y + k, 0, height - 1)) * w;
      const double weight = ky[static_cast<size_t>(k + ry)];
      for (size_t x = 0; x < w; ++x) sum[x] += weight * src[x];
    }
    float* dst = out.data() + static_cast<size_t>(y) * w;
    for (size_t x = 0; x < w; ++x) dst[x] = static_cast<float>(sum[x]);
  }
  return out;
}

// The CSF as a normalised 2D kernel is sum_i c_i * g_i(x) g_i(y) with
// normalised 1D Gaussians g_i, so it is filtered as separable terms.
struct CsfFilter {
  std::vector<std::vector<double>> gaussians;  // normalised 1D kernels
  std::vector<double> weights;                 // their share of the 2D kernel sum
};

CsfFilter make_csf_filter(const Csf& csf, double ppd) {
  const int radius = static_cast<int>(
      std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  CsfFilter filter;
  double total = 0.0;
  for (const auto& [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
    if (a == 0.0) continue;
    std::vector<double> g(2 * radius + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
      const double x = i / ppd;  // degrees
      g[i + radius] = std::exp(-std::numbers::pi * std::numbers::pi * x * x / b);
      sum += g[i + radius];
    }
    for (double& v : g) v /= sum;
    const double weight = a * std::sqrt(std::numbers::pi / b) * sum * sum;
    filter.gaussians.push_back(std::move(g));
    filter.weights.push_back(weight);
    total += weight;
  }
  for (double& w : filter.weights) w /= total;
  return filter;
}

Plane apply_csf(const Plane& in, int width, int height, const CsfFilter& filter) {
  Plane out(in.size(), 0.0f);
  for (size_t term = 0; term < filter.gaussians.size(); ++term) {
    const Plane part =
        filter_separable(in, width, height, filter.gaussians[term], filter.gaussians[term]);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = static_cast<float>(out[i] + filter.weights[term] * part[i]);
  }
  return out;
}

// A Gaussian derivative detector, separable as derivative(x) * gaussian(y);
// positive and negative weights are normalised to sum to +1 and -1.
struct FeatureFilter {
  std::vector<double> derivative;
  std::vector<double> gaussian;
};

FeatureFilter make_feature_filter(double ppd, bool points) {
  const double sd = 0.5 * kFeatureWidth * ppd;
  const int radius = static_cast<int>(std::ceil(3.0 * sd));
  FeatureFilter filter;
  filter.derivative.resize(2 * radius + 1);
  filter.gaussian.resize(2 * radius + 1);
  double gaussian_sum = 0.0, positive = 0.0, negative = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = i;
    const double g = std::exp(-x * x / (2.0 * sd * sd));
    const double d = points ? (x * x / (sd * sd) - 1.0) * g : -x * g;
    filter.gaussian[i + radius] = g;
    filter.derivative[i + radius] = d;
    gaussian_sum += g;
    (d > 0.0 ? positive : negative) += d;
  }
  for (double& g : filter.gaussian) g /= gaussian_sum;
  for (double& d : filter.derivative) d = d > 0.0 ? d / positive : d < 0.0 ? d / -negative : 0.0;
  return filter;
}

// |gradient| of the feature response at every pixel.
Plane feature_magnitude(const Plane& y, int width, int height, const FeatureFilter& filter) {
  const Plane fx = filter_separable(y, width, height, filter.derivative, filter.gaussian);
  const Plane fy = filter_separable(y, width, height, filter.gaussian, filter.derivative);
  Plane out(y.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = std::hypot(fx[i], fy[i]);
  return out;
}

struct Opponent {
  Plane y, cx, cz;
};

Opponent to_ycxcz(const ImageRGBf& image) {
  const size_t n = image.pixel_count();
  Opponent out{Plane(n), Plane(n), Plane(n)};
  for (size_t i = 0; i < n; ++i) {
    Vec3 rgb;
    for (int c = 0; c < 3; ++c) {
      const float v = image.rgb[i * 3 + c];
      rgb[c] = v > 0.0f ? std::min(v, 1.0f) : 0.0f;  // also maps NaN to 0
    }
    const Vec3 ycc = xyz_to_ycxcz(multiply(kRgbToXyz, rgb));
    out.y[i] = static_cast<float>(ycc[0]);
    out.cx[i] = static_cast<float>(ycc[1]);
    out.cz[i] = static_cast<float>(ycc[2]);
  }
  return out;
}

// Colour pipeline up to Hunt-adjusted L*a*b*, per pixel.
std::vector<Vec3> filtered_hunt_lab(const Opponent& image, int width, int height, double ppd) {
  const Plane y = apply_csf(image.y, width, height, make_csf_filter(kCsfAchromatic, ppd));
  const Plane cx = apply_csf(image.cx, width, height, make_csf_filter(kCsfRedGreen, ppd));
  const Plane cz = apply_csf(image.cz, width, height, make_csf_filter(kCsfBlueYellow, ppd));
  std::vector<Vec3> lab(y.size());
  for (size_t i = 0; i < y.size(); ++i) {
    Vec3 rgb = multiply(kXyzToRgb, ycxcz_to_xyz({y[i], cx[i], cz[i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    lab[i] = xyz_to_hunt_lab(multiply(kRgbToXyz, rgb));
  }
  return lab;
}

Plane normalized_luminance(const Opponent& image) {
  Plane y(image.y.size());
  for (size_t i = 0; i < y.size(); ++i) y[i] = (image.y[i] + 16.0f) / 116.0f;
  return y;
}

double max_colour_difference() {
  const Vec3 green = xyz_to_hunt_lab(multiply(kRgbToXyz, {0.0, 1.0, 0.0}));
  const Vec3 blue = xyz_to_hunt_lab(multiply(kRgbToXyz, {0.0, 0.0, 1.0}));
  return std::pow(hyab(green, blue), kQc);
}

}  // namespace

std::vector<float> flip_error_map(const ImageRGBf& reference_linear, const ImageRGBf& test_linear,
                                  double pixels_per_degree) {
  if (reference_linear.width != test_linear.width || reference_linear.height != test_linear.height)
    throw Error("FLIP: image sizes differ (" + std::to_string(reference_linear.width) + "x" +
                std::to_string(reference_linear.height) + " vs " +
                std::to_string(test_linear.width) + "x" + std::to_string(test_linear.height) + ")");
  if (!(pixels_per_degree > 0.0)) throw Error("FLIP: pixels per degree must be positive");
  const int width = reference_linear.width, height = reference_linear.height;
  const Opponent reference = to_ycxcz(reference_linear);
  const Opponent test = to_ycxcz(test_linear);

  const std::vector<Vec3> lab_reference = filtered_hunt_lab(reference, width, height, pixels_per_degree);
  const std::vector<Vec3> lab_test = filtered_hunt_lab(test, width, height, pixels_per_degree);

  const FeatureFilter edge = make_feature_filter(pixels_per_degree, false);
  const FeatureFilter point = make_feature_filter(pixels_per_degree, true);
  const Plane y_reference = normalized_luminance(reference);
  const Plane y_test = normalized_luminance(test);
  const Plane edges_reference = feature_magnitude(y_reference, width, height, edge);
  const Plane edges_test = feature_magnitude(y_test, width, height, edge);
  const Plane points_reference = feature_magnitude(y_reference, width, height, point);
  const Plane points_test = feature_magnitude(y_test, width, height, point);

  const double cmax = max_colour_difference();
  const double pccmax = kPc * cmax;
  std::vector<float> error(lab_reference.size());
  for (size_t i = 0; i < error.size(); ++i) {
    const double colour = std::pow(hyab(lab_reference[i], lab_test[i]), kQc);
    const double colour_error = colour < pccmax
                                    ? kPt / pccmax * colour
                                    : kPt + (colour - pccmax) / (cmax - pccmax) * (1.0 - kPt);
    const double feature_difference =
        std::max(std::abs(edges_reference[i] - edges_test[i]),
                 std::abs(points_reference[i] - points_test[i]));
    const double feature_error = std::pow(feature_difference / std::numbers::sqrt2, kQf);
    error[i] = static_cast<float>(std::pow(colour_error, 1.0 - feature_error));
  }
  return error;
}

double mean_error(const std::vector<float>& error_map) {
  if (error_map.empty()) return 0.0;
  double sum = 0.0;
  for (float e : error_map) sum += e;
  return sum / static_cast<double>(error_map.size());
}

}  // namespace cr

#include "engine/cli/compare_command.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/image_compare.h"

namespace cr {
namespace {

constexpr const char* kUsage =
    "usage: cpurender compare REFERENCE TEST [options]\n"
    "Compares two PNG images (sRGB) or two EXR images (linear R,G,B).\n"
    "Exit status: 0 pass, 1 a metric exceeds its threshold, 2 usage or input error.\n"
    "options (a metric fails when it is greater than its threshold):\n"
    "  --max-abs X          largest per-channel difference (default 0.1)\n"
    "  --rmse X             root-mean-square difference (default 0.01)\n"
    "  --pixel-threshold X  a pixel differs when a channel differs by more (default 2/255)\n"
    "  --max-fraction X     allowed fraction of differing pixels (default 0.001)\n"
    "  --flip X             mean LDR-FLIP error, 0..1 (default 0.05)\n"
    "  --ppd X              FLIP observer pixels per degree (default 67.0)\n"
    "  --diff PATH          heat map PNG written on failure (default TEST minus extension + .diff.png)\n"
    "  --diff-kind K        flip (per-pixel FLIP, default) or abs (max channel difference)\n"
    "  --json PATH          write metrics, thresholds and verdict as JSON\n"
    "  --help               show this text\n"
    "PSNR uses a peak of 1.0 and prints inf for identical images. EXR inputs are\n"
    "compared in linear values; FLIP sees them after exposure 0 EV and an ACES tonemap.\n";

struct CompareUsageError : Error {
  using Error::Error;
};

double parse_threshold(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || std::isnan(value) ||
      value < 0.0)
    throw CompareUsageError(option + " expects a non-negative number (or inf), got '" + text + "'");
  return value;
}

std::string default_diff_path(const std::string& test_path) {
  const size_t slash = test_path.find_last_of('/');
  const size_t dot = test_path.find_last_of('.');
  const bool has_extension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_extension ? test_path.substr(0, dot) : test_path) + ".diff.png";
}

}  // namespace

int compare_command(const std::vector<std::string>& args) {
  CompareThresholds thresholds;
  double ppd = kFlipDefaultPixelsPerDegree;
  std::vector<std::string> inputs;
  std::optional<std::string> diff_path, json_path;
  HeatmapKind heatmap = HeatmapKind::Flip;
  try {
    for (size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      if (arg == "--help" || arg == "-h") {
        std::cout << kUsage;
        return 0;
      }
      if (arg.size() > 1 && arg[0] == '-') {
        if (i + 1 >= args.size()) throw CompareUsageError(arg + " needs a value");
        const std::string& value = args[++i];
        if (arg == "--max-abs") thresholds.max_abs = parse_threshold(arg, value);
        else if (arg == "--rmse") thresholds.rmse = parse_threshold(arg, value);
        else if (arg == "--pixel-threshold") thresholds.pixel_threshold = parse_threshold(arg, value);
        else if (arg == "--max-fraction") thresholds.max_fraction = parse_threshold(arg, value);
        else if (arg == "--flip") thresholds.flip_mean = parse_threshold(arg, value);
        else if (arg == "--ppd") {
          ppd = parse_threshold(arg, value);
          if (!(ppd > 0.0) || std::isinf(ppd)) throw CompareUsageError("--ppd must be a positive number");
        } else if (arg == "--diff") diff_path = value;
        else if (arg == "--json") json_path = value;
        else if (arg == "--diff-kind") {
          if (value == "flip") heatmap = HeatmapKind::Flip;
          else if (value == "abs") heatmap = HeatmapKind::Difference;
          else throw CompareUsageError("--diff-kind expects flip or abs, got '" + value + "'");
        } else {
          throw CompareUsageError("unknown option " + arg);
        }
        continue;
      }
      inputs.push_back(arg);
    }
    if (inputs.size() != 2)
      throw CompareUsageError("expected two images (REFERENCE TEST), got " + std::to_string(inputs.size()));
  } catch (const CompareUsageError& e) {
    std::cerr << "cpurender compare: " << e.what() << "\n" << kUsage;
    return 2;
  }

  try {
    const CompareResult result = compare_image_files(inputs[0], inputs[1], thresholds, ppd);
    std::cout << "reference " << inputs[0] << "\ntest      " << inputs[1] << "\n"
              << format_compare_result(result, thresholds);
    for (const std::string& failure : result.failures) std::cout << "  failed: " << failure << "\n";
    if (json_path) {
      nlohmann::json doc = compare_result_to_json(result, thresholds);
      doc["reference"] = inputs[0];
      doc["test"] = inputs[1];
      write_file_atomic(*json_path, doc.dump(2) + "\n");
    }
    if (!result.pass) {
      const std::string path = diff_path.value_or(default_diff_path(inputs[1]));
      write_error_heatmap(path, result, heatmap);
      std::cout << "difference heat map ("
                << (heatmap == HeatmapKind::Flip ? "FLIP, 0..1" : "max channel difference, scaled to its maximum")
                << "): " << path << "\n";
    }
    return result.pass ? 0 : 1;
  } catch (const Error& e) {
    std::cerr << "cpurender compare: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace cr

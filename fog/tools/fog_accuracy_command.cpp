// fog-accuracy: measure_fog_accuracy, printed. Each line: grid, fog pass
// time, composite time, mean and p95 relative luminance error of the final
// image; then the reference's time. A fixed-point profile adds the temporal
// configuration in float and the fixed-point frame's error against it.
#include <cstdio>
#include <string>

#include "engine/core/error.h"
#include "fog/tools/fog_accuracy.h"
#include "engine/cli/cli_common.h"
#include "fog/tools/fog_command_common.h"
#include "fog/tools/fog_commands.h"

namespace cr {

int fog_accuracy_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser a("fog-accuracy", "cpurender fog-accuracy SCENE [options]",
              "Froxel fog vs the per-pixel ray-marched reference on one frame: temporal grid, single frame,\n"
              "2x resolution; mean and p95 relative luminance error and the time of each.");
  add_fog_command_options(a);
  a.option("frame", "N", "frame of the scene to measure", "0")
      .option("samples", "N", "reference samples per pixel", "512")
      .option("warmup", "N", "history frames before the temporal measurement", "14");
  if (!a.parse(args, 1, 1)) return 0;
  // Bad numbers are reported before the scene is loaded.
  const int frame = a.get_int("frame", 0, 1000000);
  const int samples = a.get_int("samples", 1, 65536);
  const int warmup = a.get_int("warmup", 0, 1000);
  const FogRun run = load_fog_run(a, registry);
  JobSystem jobs(threads_option(a));

  const FogAccuracy result = measure_fog_accuracy(run, registry, jobs, frame, samples, warmup);
  std::printf("fog-accuracy %s frame %d, %dx%d, %u threads, reference %d samples/pixel\n", run.description.path.c_str(),
              frame, result.width, result.height, jobs.thread_count(), samples);
  std::printf("%-16s %-12s %10s %12s %10s %10s\n", "config", "froxels", "passes ms", "composite ms", "mean err",
              "p95 err");
  auto print = [](const FogAccuracyRow& r) {
    const std::string dims = std::to_string(r.nx) + "x" + std::to_string(r.ny) + "x" + std::to_string(r.nz);
    std::printf("%-16s %-12s %10.2f %12.2f %10.4f %10.4f\n", r.config.c_str(), dims.c_str(), r.passes_ms,
                r.composite_ms, r.error.mean, r.error.p95);
  };
  for (const FogAccuracyRow& r : result.rows) print(r);
  if (result.float_temporal) print(*result.float_temporal);
  std::printf("%-16s %-12s %10.1f\n", "reference", "per pixel", result.reference_ms);
  if (result.fixed_against_float)
    std::printf("fixed point against float (temporal): mean %.5f, p95 %.5f relative luminance error\n",
                result.fixed_against_float->mean, result.fixed_against_float->p95);
  return 0;
}

}  // namespace cr

#pragma once
// The froxel fog against the per-pixel ray-marched reference on one frame of
// a scene (what fog-accuracy prints), for three froxel configurations:
//   temporal         the profile's grid after `warmup` frames of history (static view)
//   single           the same grid, one frame, no reprojection
//   2x non-temporal  twice the resolution in x, y and z, no jitter, no reprojection
#include <string>
#include <vector>

#include "engine/core/job_system.h"
#include "fog/tools/fog_command_common.h"

namespace cr {

struct FogAccuracyRow {
  std::string config;
  int nx = 0, ny = 0, nz = 0;  // the froxel grid
  double passes_ms = 0, composite_ms = 0;  // the measured (last) frame's
  ImageError error;                        // of the final image against the reference's
};
struct FogAccuracy {
  int width = 0, height = 0;
  std::vector<FogAccuracyRow> rows;  // temporal, single, 2x non-temporal
  double reference_ms = 0;
};
FogAccuracy measure_fog_accuracy(const FogRun& run, const PluginRegistry& registry, JobSystem& jobs, int frame,
                                 int samples, int warmup);

}  // namespace cr

#pragma once
// The froxel fog against the per-pixel ray-marched reference on one frame of
// a scene (what fog-accuracy prints), for three froxel configurations:
//   temporal         the profile's grid after `warmup` frames of history (static view)
//   single           the same grid, one frame, no reprojection
//   2x non-temporal  twice the resolution in x, y and z, no jitter, no reprojection
// With "precision": "fixed", also the temporal frame against the same
// configuration in float: the error the reduced precision adds.
#include <optional>
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
  std::optional<FogAccuracyRow> float_temporal;  // fixed-point profiles: the temporal row in float
  std::optional<ImageError> fixed_against_float;  // ... and the fixed-point temporal frame against it
};
FogAccuracy measure_fog_accuracy(const FogRun& run, const PluginRegistry& registry, JobSystem& jobs, int frame,
                                 int samples, int warmup);

}  // namespace cr

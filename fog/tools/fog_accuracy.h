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
#include "fog/tools/fog_reference.h"

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

// The parts sweep --truth shares:
// the per-pixel reference of the base renderer's current frame (`view`), and
// the reference's final image: the base colour seen through its fog.
FogReferenceImage render_fog_reference(const FogRun& run, const Renderer& base, const FrameView& view, int samples,
                                       JobSystem& jobs);
std::vector<glm::vec3> fog_reference_composite(const Renderer& base, const FogReferenceImage& ref);
// A froxel configuration run for `frames` frames of the static view (history
// after the first), measured against `reference`; its last image in `image`.
struct FroxelConfig {
  const char* name;
  FogProfileSettings profile;
  int frames;
};
// The temporal configuration: the profile's grid after `warmup` frames of history, when it reprojects.
FroxelConfig temporal_config(const FogProfileSettings& profile, int warmup);
FogAccuracyRow measure_froxel_config(const FogRun& run, const Renderer& base, const FrameView& view, JobSystem& jobs,
                                     const FroxelConfig& config, const std::vector<glm::vec3>& reference,
                                     std::vector<glm::vec3>& image);

}  // namespace cr

#pragma once
// One cell of the fog's stability map: the froxel fog over a few frames of a
// synthetic view (uniform fog, a wall's light shaft, a camera moving sideways
// at a constant speed), its last frame against the ray-marched reference
// (optional: the tests skip it), non-finite values in every frame's volume and
// image, and where the history was rejected: of the froxels whose history was
// read, the share without history (outside the previous frustum,
// ReprojectStats::rejected) and the share clamped to the current 3x3 range
// (ReprojectStats::clamped), averaged over the frames that had history. A
// moving camera with the clamp reads only froxels whose 3x3 range is not one
// value (fully lit or shadowed air blends to its current value unread), so
// the shares are of the froxels where history could matter.
#include <cstddef>

#include "engine/core/job_system.h"
#include "fog/fog_settings.h"
#include "fog/tools/fog_command_common.h"

namespace cr {

struct FogStabilityCase {
  float extinction = 0.05f;  // 1/m, uniform
  float anisotropy = 0.0f;   // HG g
  float speed = 0.0f;        // camera m/frame, sideways across the shaft
  bool reprojection = true;
  float history_weight = 6.0f / 7.0f;
  int froxel_size_px = 8;
  int frames = 8;
};

struct FogStabilityOptions {
  int width = 160, height = 96;
  bool reference = true;
  int samples = 128;  // the reference's segments per pixel; its noise is measured against half as many
};

struct FogStabilityCell {
  ImageError error;        // the last frame against the reference
  ImageError noise;        // the reference at samples / 2 against samples: its convergence error
  size_t non_finite = 0;   // every frame's integrated volume (active froxels) and composited image
  size_t non_finite_reference = 0;
  double history_rejected = 0.0;  // mean share of the read froxels without history
  double history_clamped = 0.0;   // mean share of the read froxels whose history was clamped
  double history_read = 0.0;      // mean share of the lit froxels whose history was read
  double passes_ms = 0.0, ref_ms = 0.0;
};

FogStabilityCell evaluate_fog_stability(const FogStabilityCase& c, const FogStabilityOptions& options, JobSystem& jobs);

}  // namespace cr

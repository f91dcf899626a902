#pragma once
// The participating medium of a scene: exponential height fog plus local
// oriented-box volumes blended over it in file order. Evaluated at points
// given relative to the camera (camera-relative rendering: the camera's double
// position is subtracted once per frame, so float stays precise far from the
// origin). Shared by the froxel voxelisation and the reference ray marcher,
// so both see exactly the same density.
#include <vector>

#include <glm/glm.hpp>

#include "fog/fog_settings.h"

namespace cr {

// Scattering (RGB, 1/m) and extinction (1/m) at a point.
struct FogDensity {
  glm::vec3 scattering{0.0f};
  float extinction = 0.0f;
};

// A volume placed relative to this frame's camera.
struct PlacedFogVolume {
  glm::vec3 center;  // relative to the camera
  glm::vec3 axes[3];
  glm::vec3 half_size;
  float fade;
  FogDensity density;  // albedo * extinction, extinction
  FogBlend blend;
  FogNoise noise;
  int source_index;    // index in FogSceneSettings::volumes
};

class FogMedium {
 public:
  FogMedium() = default;
  explicit FogMedium(const FogSceneSettings& settings);
  // Places the volumes relative to the camera; zero-size volumes are dropped.
  void set_camera(const glm::dvec3& camera_position);

  const std::vector<PlacedFogVolume>& volumes() const { return placed_; }
  bool has_height_fog() const { return settings_.height_fog; }

  FogDensity height_fog(const glm::vec3& rel) const;
  // Blends volume v over `dst` at `rel` (no-op outside the box).
  void apply_volume(const PlacedFogVolume& v, const glm::vec3& rel, FogDensity& dst) const;
  // Height fog then every volume in order.
  FogDensity sample(const glm::vec3& rel) const;

 private:
  FogSceneSettings settings_;
  float inv_scale_height_ = 0.0f;
  float base_rel_ = 0.0f;  // base height relative to the camera
  std::vector<PlacedFogVolume> placed_;
};

}  // namespace cr

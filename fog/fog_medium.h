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

  // Height fog: extinction * exp(-(h - base) / H) above the base. Above
  // base + 2 (max_height - base) the density is below 1e-6 of the base
  // (H = (max - base) / ln 1000) and is taken as exactly zero, so the passes
  // skip clear air; what is dropped is < 1e-6 of the layer's optical depth.
  FogDensity height_fog(const glm::vec3& rel) const;
  // height_fog at dir * t[k] for k < n (one froxel column), same values.
  void height_fog_column(const glm::vec3& dir, const float* t, int n, FogDensity* out) const;
  // Blends volume v over `dst` at `rel`; false (and a no-op) outside the box.
  bool apply_volume(const PlacedFogVolume& v, const glm::vec3& rel, FogDensity& dst) const;
  // Height fog then every volume in order.
  FogDensity sample(const glm::vec3& rel) const;

 private:
  FogSceneSettings settings_;
  float inv_scale_height_ = 0.0f;
  float base_rel_ = 0.0f;  // base height relative to the camera
  float cutoff_above_ = 0.0f;  // height above the base where the fog is clear air
  std::vector<PlacedFogVolume> placed_;
};

}  // namespace cr

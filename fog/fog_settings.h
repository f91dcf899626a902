#pragma once
// The fog plugin's validated inputs: the profile's "fog" section (grid size,
// range, temporal options) and the scene's "fog" section (height fog, local
// volumes, phase function). Defaults follow Unity HDRP (seed 002).
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cr {

// How the froxel buffers are stored and blended (profile "precision"):
// float, or 16-bit fixed point as a phone stores fp16/unorm16 textures
// (docs/fog.md, "Reduced precision (mobile)").
enum class FogPrecision { Float, Fixed };

// Profile "fog" section.
struct FogProfileSettings {
  int froxel_size_px = 8;          // screen pixels per froxel edge (HDRP: 1/8 screen)
  int slices = 64;                 // depth slices
  float fog_distance = 64.0f;      // metres covered by the grid beyond the near plane
  float slice_uniformity = 0.75f;  // 0 = logarithmic slices, 1 = linear
  int density_samples = 4;         // points per slice averaged where local volumes lie (1 = centre)
  float history_weight = 6.0f / 7.0f;
  bool filter = true;              // 3x3 Gaussian per slice
  bool jitter = true;              // 7-frame sample sequence
  bool reprojection = true;        // temporal blend with the reprojected history
  bool history_clamp = true;       // clamp history to the current 3x3 neighbourhood (less ghosting)
  bool light_change_rejection = true;  // trust history less where a moving sun changed the sample's visibility
  bool still_accumulation = true;  // a still view (same camera and sun) averages the jitter sequence evenly, unclamped,
                                   // and drops the filter once a whole sequence is in
  bool still_settled = false;  // opt-in: a still view lights again only froxels whose 3x3x3 history is not one 0 or 1
                               // (misses occluders thinner than a froxel that two samples missed)
  FogPrecision precision = FogPrecision::Float;
};

enum class FogPhase { HenyeyGreenstein, CornetteShanks };
enum class FogBlend { Overwrite, Additive, Multiply, Min, Max };

// Optional procedural density of a volume: fractal value noise.
struct FogNoise {
  bool enabled = false;
  float scale = 4.0f;      // metres per noise cell of the first octave
  int octaves = 3;
  float strength = 1.0f;   // 0 = no effect, 1 = density fully modulated
};

// An oriented box of fog. Axes are unit and orthogonal (world space).
struct FogVolume {
  glm::dvec3 center{0.0};
  glm::vec3 half_size{1.0f};  // metres, along axes[0..2]; 0 = empty volume
  glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  float extinction = 0.1f;    // 1/m (1 / mean free path)
  glm::vec3 albedo{1.0f};
  float fade = 0.0f;          // metres inside each face over which the volume fades in
  FogBlend blend = FogBlend::Additive;
  FogNoise noise;
};

// Scene "fog" section.
struct FogSceneSettings {
  bool height_fog = false;
  float base_height = 0.0f;    // metres; full density below
  float max_height = 50.0f;    // density falls to 0.001 of the base at this height (HDRP)
  float extinction = 0.02f;    // 1/m at the base height
  glm::vec3 albedo{1.0f};
  std::vector<FogVolume> volumes;  // applied in file order after the height fog
  FogPhase phase = FogPhase::HenyeyGreenstein;
  float anisotropy = 0.0f;     // g in (-1, 1)
  float distance = 0.0f;       // > 0: the scene's fog range, replacing the profile's fog_distance
};

// Whether the scene's fog has anything to scatter in: height fog or a volume.
inline bool has_fog_media(const FogSceneSettings& s) { return s.height_fog || !s.volumes.empty(); }

// Throws InputError(file, "fog.<field>: ...") on unknown keys or bad values.
FogProfileSettings parse_fog_profile(const nlohmann::json& section, const std::string& file);
FogSceneSettings parse_fog_scene(const nlohmann::json& section, const std::string& file);
// The profile's settings with the scene's overrides (HDRP: the volumetric
// fog distance is an artist setting of the scene).
FogProfileSettings resolve_fog_settings(const FogProfileSettings& profile, const FogSceneSettings& scene);

}  // namespace cr

#pragma once
// What the fog commands share: option parsing, loading a scene and profile,
// rendering the fog-free base frame with the engine (depth, shadow map and
// the light the atmosphere provides), running a froxel configuration on it,
// and the image error metric.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/profile.h"
#include "engine/render/plugin_registry.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene.h"
#include "engine/cli/arg_parser.h"
#include "engine/scene/scene_description.h"
#include "fog/froxel_fog.h"

namespace cr {

// The options every fog command takes: --profile, --resolution, --threads.
void add_fog_command_options(ArgParser& p);

struct FogRun {
  SceneDescription description;
  Profile profile;
  std::shared_ptr<const Scene> scene;
  FogSceneSettings fog_scene;
  FogProfileSettings fog_profile;
};
// Loads scene, profile (a path, or a name under <exe dir>/profiles) and glTF;
// the scene must have a "fog" section.
FogRun load_fog_run(const ArgParser& args, const PluginRegistry& registry);
// A run of a loaded scene and profile: its fog settings. InputError when the
// scene has no "fog" section or the profile renders at another size than its output.
FogRun make_fog_run(SceneDescription description, Profile profile, std::shared_ptr<const Scene> scene);

// The run's scene with the sun's azimuth turning `degrees_per_frame` over
// frames [0, frames) from its direction in `first` (frame 0's view), at the
// same elevation and illuminance: light shafts that move.
SceneDescription with_turning_sun(const SceneDescription& scene, const FrameView& first, int frames,
                                  double degrees_per_frame);

// The registry's plugins except the fog: the engine's base image.
std::vector<std::unique_ptr<Plugin>> plugins_without_fog(const PluginRegistry& registry);

// Times (ms) of one froxel frame's steps.
struct FroxelTimes {
  double density = 0, lighting = 0, reproject = 0, filter = 0, integrate = 0, composite = 0;
  double passes() const { return density + lighting + reproject + filter + integrate; }
};
// Renders one froxel frame over the base renderer's current frame and
// returns the composited colour.
std::vector<glm::vec3> froxel_frame(FroxelFog& fog, const FrameView& view, const Renderer& base, JobSystem& jobs,
                                    FroxelTimes* times);

// Per-pixel relative luminance error |Y - Y_ref| / max(Y_ref, floor): mean and 95th percentile.
struct ImageError {
  double mean = 0, p95 = 0;
};
ImageError relative_luminance_error(const std::vector<glm::vec3>& reference, const std::vector<glm::vec3>& test);

}  // namespace cr

#pragma once
// The fog's ground truth for sweep --truth: fog-accuracy's temporal row for
// the point's profile at the measured frame. The froxel fog of the point's
// fog settings, run on a static view of that frame for its warm-up of
// history, against the per-pixel ray-marched reference over the same
// fog-free base frame (same depth, shadow map and light).
#include "engine/cli/module_truth.h"
#include "engine/render/plugin_registry.h"

namespace cr {

// Renders through `plugins` (every plugin but the fog makes the base frame).
ModuleTruth fog_truth(const PluginRegistry& plugins);

}  // namespace cr

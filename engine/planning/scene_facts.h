#pragma once
// The facts the `auto` planner reads from a scene before rendering it: the
// camera's and the sun's motion over the frames to render, their extremes,
// and how far the geometry reaches from the camera.
#include "engine/render/module_plan.h"

namespace cr {

// Evaluates the scene's camera and sun at frames [0, frames) at the output
// resolution (make_frame_view: the frames the renderer will draw).
SceneFacts analyse_scene(const Scene& scene, const SceneDescription& description, int frames, int width,
                         int height);

}  // namespace cr

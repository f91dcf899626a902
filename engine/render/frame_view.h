#pragma once
// The camera and sun of a frame, from the scene description: a pure function
// of (scene, description, frame), so any frame can be rendered on its own.
#include "engine/render/plugin.h"

namespace cr {

FrameView make_frame_view(const Scene& scene, const SceneDescription& description, int frame, int width,
                          int height);

// Whether the description views the scene through an orthographic glTF
// camera (plugins built on perspective froxels and sky views skip such views).
bool orthographic_view(const Scene& scene, const SceneDescription& description);

// Unit direction towards the sun for an azimuth (clockwise from +Z towards +X)
// and elevation above the horizon, in degrees.
glm::vec3 sun_direction(float azimuth_deg, float elevation_deg);

}  // namespace cr

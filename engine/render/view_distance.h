#pragma once
// Distance along the view ray from reversed-Z depth alone (view depth =
// znear / z for a perspective camera, the linear range of an orthographic
// one), so passes that need only depth (fog) can run before shading. The ray
// through screen position (px, py) is forward + sx right + sy up, so
// distance = view depth * sqrt(1 + sx^2 + sy^2).
#include <vector>

#include "engine/core/job_system.h"
#include "engine/scene/camera.h"

namespace cr {

// Metres along the ray through screen position (px, py) (pixels; the centre
// of pixel (x, y) is x + 0.5, y + 0.5) of a w x h image at `depth`; +inf for
// depth 0 (nothing drawn).
float view_distance(const Camera& cam, int w, int h, float px, float py, float depth);
// The same with the image's rays prepared once (`rays` of `cam` and the image).
float view_distance(const Camera& cam, const PixelRays& rays, float px, float py, float depth);

// view_distance at every pixel centre: distance[i] for depth[i], row-major.
void view_distances(const Camera& cam, int w, int h, const std::vector<float>& depth, std::vector<float>& distance,
                    JobSystem& jobs);

}  // namespace cr

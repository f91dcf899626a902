#pragma once
// Sun shadow map: an orthographic depth image seen from the sun, fitted to the
// part of the view frustum within Profile::shadow_distance, texel-snapped so it
// does not shimmer when the camera moves. Rendered by the rasterizer
// (depth-only, same fill rules); sampled with PCF by shading and by the fog.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/camera.h"

namespace cr {

// Points whose shadow is looked up together (structure of arrays, so that
// their projection into the map vectorises).
struct ShadowReceivers {
  static constexpr int kCapacity = 64;
  int count = 0;
  float px[kCapacity], py[kCapacity], pz[kCapacity];  // world position
  float nx[kCapacity], ny[kCapacity], nz[kCapacity];  // normal, as for ShadowMap::visibility
};

struct ShadowMap {
  int size = 0;                 // size x size texels; 0 = no shadow map (everything lit)
  glm::dvec3 origin{0.0};       // world origin the projection is relative to (texel-snapped)
  glm::mat4 light_view_proj{1.0f};  // (world - origin) -> clip; ortho, z in [0,1], 1 = nearest the sun
  float texel_world_size = 1.0f;    // metres per texel
  float depth_range = 1.0f;         // metres covered by z in [0,1]
  glm::vec3 direction_to_sun{0.0f, 1.0f, 0.0f};
  int pcf_radius = 1;
  // The projection's placement, which decides whether a later frame's map
  // can scroll from this one (shadow_scroll.h): the origin in texels along
  // the light's x and y axes, its depth along direction_to_sun, and the
  // interval [depth_min, depth_max] (metres from the origin towards the sun)
  // that z in [0, 1] covers.
  int64_t grid_x = 0, grid_y = 0;
  double origin_depth = 0.0;
  double depth_min = 0.0, depth_max = 0.0;
  std::vector<float> depth;     // size*size, reversed (1 = nearest the sun, 0 = empty)

  // Fraction of the sun visible at a world point in [0, 1] (1 = lit). `normal`
  // (unit, may be zero) drives the normal-offset and slope-scaled biases.
  float visibility(const glm::vec3& world_pos, const glm::vec3& normal) const;
  // visibility() of every receiver: out[k] for point k, the same floats.
  void visibility(const ShadowReceivers& points, float* out) const;
};

// What a view asks of the sun's shadow map: the light's axes, the texel
// size, the texel-snapped origin and the depth interval it must cover.
struct ShadowFit {
  glm::dvec3 axis_x{1.0, 0.0, 0.0}, axis_y{0.0, 0.0, 1.0}, axis_z{0.0, 1.0, 0.0};  // axis_z towards the sun
  int size = 0;
  double texel = 1.0;  // metres
  int64_t grid_x = 0, grid_y = 0;  // the snapped origin, in texels along axis_x and axis_y
  double centre_depth = 0.0;       // the view's centre along axis_z
  // Metres from centre_depth towards the sun that receivers (the view's
  // slice) and casters (the scene's bounds) span.
  double need_min = 0.0, need_max = 0.0;
};
ShadowFit fit_shadow_view(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance, int size,
                          const glm::vec3& scene_min, const glm::vec3& scene_max);

// The orthographic projection of `fit`'s texel grid with its origin at
// `origin_depth` along the light's axis, z in [0, 1] covering [depth_min,
// depth_max] from there; an empty depth image.
ShadowMap shadow_projection(const ShadowFit& fit, int pcf_radius, double origin_depth, double depth_min,
                            double depth_max);

// Chooses the shadow projection for a view (the fit's own depth interval),
// with an empty depth image (reads as lit everywhere).
ShadowMap fit_shadow_projection(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance,
                                int size, int pcf_radius, const glm::vec3& scene_min, const glm::vec3& scene_max);

// fit_shadow_projection with the depth image allocated and cleared (no
// occluder recorded), ready to be rendered or written.
ShadowMap fit_shadow_map(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance,
                         int size, int pcf_radius, const glm::vec3& scene_min, const glm::vec3& scene_max);

}  // namespace cr

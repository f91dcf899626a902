#include "engine/planning/scene_facts.h"

#include <algorithm>
#include <cmath>

#include "engine/render/frame_view.h"

namespace cr {

namespace {

double angle_deg(const glm::vec3& a, const glm::vec3& b) {
  const double c = std::clamp(double(glm::dot(a, b)), -1.0, 1.0);
  return glm::degrees(std::acos(c));
}

// The farthest corner of the box from the point: no geometry lies farther.
double farthest_corner(const glm::dvec3& p, const glm::vec3& lo, const glm::vec3& hi) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = std::max(std::abs(p[i] - double(lo[i])), std::abs(p[i] - double(hi[i])));
    d2 += e * e;
  }
  return std::sqrt(d2);
}

// The share of the view the box's projected rectangle covers: 1 when a
// corner lies behind the camera's near plane (the camera among the bounds).
double screen_coverage(const Camera& camera, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::mat4 view_proj = camera.view_proj();
  glm::vec2 a(1.0f), b(-1.0f);
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec4 c = view_proj * glm::vec4(glm::vec3(corner - camera.position), 1.0f);
    if (!(c.w > 0.0f)) return 1.0;
    const glm::vec2 ndc = glm::clamp(glm::vec2(c) / c.w, glm::vec2(-1.0f), glm::vec2(1.0f));
    a = glm::min(a, ndc);
    b = glm::max(b, ndc);
  }
  return b.x > a.x && b.y > a.y ? double(b.x - a.x) * double(b.y - a.y) / 4.0 : 0.0;
}

}  // namespace

SceneFacts analyse_scene(const Scene& scene, const SceneDescription& description, int frames, int width,
                         int height) {
  SceneFacts f;
  f.frames = std::max(1, frames);
  f.width = width;
  f.height = height;
  f.has_geometry = !scene.draws.empty();
  FrameView prev;
  for (int i = 0; i < f.frames; ++i) {
    const FrameView v = make_frame_view(scene, description, i, width, height);
    const double elevation = glm::degrees(std::asin(std::clamp(double(v.sun_direction.y), -1.0, 1.0)));
    const double height_m = v.camera.position.y;
    f.min_sun_elevation_deg = std::min(f.min_sun_elevation_deg, elevation);
    f.max_sun_elevation_deg = std::max(f.max_sun_elevation_deg, elevation);
    f.min_camera_height_m = i == 0 ? height_m : std::min(f.min_camera_height_m, height_m);
    f.max_camera_height_m = i == 0 ? height_m : std::max(f.max_camera_height_m, height_m);
    if (f.has_geometry) {
      f.max_geometry_distance_m =
          std::max(f.max_geometry_distance_m, farthest_corner(v.camera.position, scene.bounds_min, scene.bounds_max));
      f.max_geometry_coverage =
          std::max(f.max_geometry_coverage, screen_coverage(v.camera, scene.bounds_min, scene.bounds_max));
    }
    if (i > 0) {
      f.max_camera_speed_m = std::max(f.max_camera_speed_m, glm::length(v.camera.position - prev.camera.position));
      f.max_camera_turn_deg = std::max(f.max_camera_turn_deg, angle_deg(v.camera.forward, prev.camera.forward));
      f.max_sun_turn_deg = std::max(f.max_sun_turn_deg, angle_deg(v.sun_direction, prev.sun_direction));
    }
    prev = v;
  }
  return f;
}

}  // namespace cr

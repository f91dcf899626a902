#include "engine/render/frame_view.h"

#include <algorithm>
#include <cmath>

namespace cr {

glm::vec3 sun_direction(float azimuth_deg, float elevation_deg) {
  const double az = glm::radians(double(azimuth_deg)), el = glm::radians(double(elevation_deg));
  return glm::normalize(glm::vec3(glm::dvec3(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el))));
}

namespace {

// Index of the key segment containing `frame` and the blend factor in it.
template <class Key>
std::pair<size_t, double> segment(const std::vector<Key>& keys, int frame) {
  if (frame <= keys.front().frame) return {0, 0.0};
  for (size_t i = 0; i + 1 < keys.size(); ++i)
    if (frame < keys[i + 1].frame)
      return {i, double(frame - keys[i].frame) / double(keys[i + 1].frame - keys[i].frame)};
  return {keys.size() - 1, 0.0};
}

// The view a model viewer opens with: from the front-right (glTF models face
// +Z), somewhat above, the bounding sphere filling the narrower field of view.
Camera three_quarter_view(const Scene& scene, float aspect) {
  const glm::dvec3 lo(scene.framing_min), hi(scene.framing_max);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(1e-3, 0.5 * glm::length(hi - lo));
  const float vfov = glm::radians(40.0f);
  const double half_fov = std::min(0.5 * double(vfov), std::atan(std::tan(0.5 * double(vfov)) * double(aspect)));
  const double dist = radius / std::sin(half_fov) * 1.05;
  const double az = glm::radians(35.0), el = glm::radians(15.0);
  const glm::dvec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  return Camera::look_at(centre + dir * dist, centre, vfov, aspect, float(std::max(1e-4, (dist - radius) * 0.5)));
}

Camera camera_for(const Scene& scene, const SceneDescription& d, int frame, float aspect, bool* cut) {
  *cut = false;
  const CameraSpec& spec = d.camera;
  if (spec.auto_frame) return three_quarter_view(scene, aspect);
  if (!spec.keys.empty()) {
    auto [i, t] = segment(spec.keys, frame);
    const CameraKey& a = spec.keys[i];
    const CameraKey& b = spec.keys[std::min(i + 1, spec.keys.size() - 1)];
    for (const CameraKey& k : spec.keys) *cut = *cut || (k.cut && k.frame == frame && frame > 0);
    const glm::dvec3 pos = glm::mix(a.position, b.position, t);
    const glm::dvec3 target = glm::mix(a.target, b.target, t);
    const float vfov = float(glm::mix(double(a.vfov_deg), double(b.vfov_deg), t));
    return Camera::look_at(pos, target, glm::radians(vfov), aspect, spec.znear);
  }
  const int index = spec.gltf_camera.value_or(0);
  if (index < int(scene.cameras.size())) {
    const GltfCamera& c = scene.cameras[index];
    Camera cam = Camera::look_at(glm::dvec3(c.position), glm::dvec3(c.position) + glm::dvec3(c.forward),
                                 c.yfov_rad, aspect, c.znear);
    if (c.orthographic) {
      // ymag is the half-height; the width follows the image's aspect, as
      // yfov does for perspective cameras.
      cam.orthographic = true;
      cam.ortho_half_height = c.ymag;
      cam.zfar = c.zfar;
    }
    return cam;
  }
  return three_quarter_view(scene, aspect);
}

}  // namespace

bool orthographic_view(const Scene& scene, const SceneDescription& d) {
  if (d.camera.auto_frame || !d.camera.keys.empty()) return false;
  const size_t index = size_t(d.camera.gltf_camera.value_or(0));
  return index < scene.cameras.size() && scene.cameras[index].orthographic;
}

FrameView make_frame_view(const Scene& scene, const SceneDescription& d, int frame, int width, int height) {
  FrameView v;
  v.frame = frame;
  v.width = width;
  v.height = height;
  const float aspect = float(width) / float(height);
  bool cut = false;
  v.camera = camera_for(scene, d, frame, aspect, &cut);
  bool prev_cut = false;
  v.prev_camera = frame > 0 ? camera_for(scene, d, frame - 1, aspect, &prev_cut) : v.camera;
  v.history_valid = frame > 0 && !cut;
  if (!v.history_valid) v.prev_camera = v.camera;

  const SunSpec& sun = d.sun;
  if (!sun.keys.empty()) {
    auto [i, t] = segment(sun.keys, frame);
    const SunKey& a = sun.keys[i];
    const SunKey& b = sun.keys[std::min(i + 1, sun.keys.size() - 1)];
    v.sun_direction = sun_direction(float(glm::mix(double(a.azimuth_deg), double(b.azimuth_deg), t)),
                                    float(glm::mix(double(a.elevation_deg), double(b.elevation_deg), t)));
    v.sun_illuminance = sun.color * sun.illuminance;
  } else if (scene.sun) {
    // Direction and colour from KHR_lights_punctual; the illuminance stays the
    // scene file's, since exporters write arbitrary intensities for suns.
    v.sun_direction = scene.sun->direction_to_sun;
    v.sun_illuminance = scene.sun->color * sun.illuminance;
  } else {
    // No sun anywhere: light from over the three-quarter view's right shoulder.
    v.sun_direction = sun_direction(75.0f, 45.0f);
    v.sun_illuminance = sun.color * sun.illuminance;
  }
  return v;
}

}  // namespace cr

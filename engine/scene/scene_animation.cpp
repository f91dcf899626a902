#include "engine/scene/scene_animation.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/error.h"
#include "engine/scene/animation_sampling.h"
#include "engine/scene/mesh_deformation.h"
#include "engine/scene/scene_description.h"

namespace cr {

namespace {

bool usable_direction(const glm::dvec3& v) {
  const double len = glm::length(v);
  return std::isfinite(len) && len > 0.0;
}

bool finite_matrix(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

glm::dvec3 sample_vec3(const AnimationSampler& sampler, double time_s) {
  const std::vector<double> v = sample_values(sampler, time_s);
  return glm::dvec3(v[0], v[1], v[2]);
}

void apply_animation(const AnimationClip& clip, double time_s, std::vector<NodeTransform>& transforms,
                     std::vector<std::vector<float>>& weights) {
  for (const AnimationChannel& channel : clip.channels) {
    NodeTransform& t = transforms[channel.node];
    switch (channel.path) {
      case AnimationPath::Translation: t.translation = sample_vec3(channel.sampler, time_s); break;
      case AnimationPath::Rotation: t.rotation = sample_rotation(channel.sampler, time_s); break;
      case AnimationPath::Scale: t.scale = sample_vec3(channel.sampler, time_s); break;
      case AnimationPath::Weights: {
        const std::vector<double> w = sample_values(channel.sampler, time_s);
        weights[channel.node].assign(w.begin(), w.end());
        break;
      }
    }
  }
}

void world_bounds(const glm::mat4& world, const glm::vec3& lo, const glm::vec3& hi, glm::vec3& out_lo,
                  glm::vec3& out_hi) {
  out_lo = glm::vec3(std::numeric_limits<float>::infinity());
  out_hi = -out_lo;
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
    glm::vec3 w = glm::vec3(world * glm::vec4(p, 1.0f));
    out_lo = glm::min(out_lo, w);
    out_hi = glm::max(out_hi, w);
  }
}

// Places what one pose's node world matrices put into the scene.
class PosePlacer {
 public:
  PosePlacer(Scene& scene, const SceneAnimation& data, const std::vector<glm::dmat4>& world, std::string when)
      : scene_(scene), data_(data), world_(world), when_(std::move(when)) {}

  void place(int n, const std::vector<float>& weights) {
    const SceneNode& node = data_.nodes[n];
    if (node.mesh >= 0) place_mesh(n, weights);
    if (node.camera >= 0) place_camera(n);
    if (node.light >= 0) place_light(n);
    if (node.sun) place_sun(n);
  }

  // Node instances (a node without instancing is one) not drawn for a
  // singular or non-finite world matrix.
  size_t degenerate() const { return degenerate_; }

 private:
  [[noreturn]] void fail(int n, const std::string& what) const {
    const std::string& name = data_.nodes[n].name;
    throw InputError(scene_.source, "node " + std::to_string(n) + (name.empty() ? "" : " '" + name + "'") + " " +
                                        what + " with a degenerate transform" + when_);
  }

  void place_mesh(int n, const std::vector<float>& weights) {
    const SceneNode& node = data_.nodes[n];
    const MeshDeformation& deformation = data_.deformations[node.mesh];
    std::vector<glm::dmat4> joints;
    if (node.skin >= 0) {
      const SceneSkin& skin = data_.skins[node.skin];
      joints.resize(skin.joints.size());
      for (size_t j = 0; j < joints.size(); ++j) joints[j] = world_[skin.joints[j]] * skin.inverse_bind[j];
    }
    const Mesh& rest = scene_.meshes[node.mesh];
    // Skinned vertices are in world space: the glTF spec has the skinned
    // node's own transform ignored.
    auto skinned = [&](size_t p) { return !joints.empty() && deformation.primitives[p].skinnable(); };
    if (node.posed_mesh >= 0) {
      const std::vector<glm::dmat4> unskinned;
      for (size_t p = 0; p < rest.primitives.size(); ++p) {
        deform_primitive(rest.primitives[p], deformation.primitives[p], weights, skinned(p) ? joints : unskinned,
                         scene_.meshes[node.posed_mesh].primitives[p]);
      }
    }
    const int drawn_mesh = node.posed_mesh >= 0 ? node.posed_mesh : node.mesh;
    const size_t instances = std::max<size_t>(1, node.instances.size());
    for (size_t i = 0; i < instances; ++i) {
      const glm::dmat4 instance = node.instances.empty() ? glm::dmat4(1.0) : node.instances[i];
      bool dropped = false;
      for (size_t p = 0; p < rest.primitives.size(); ++p) {
        dropped |= !add_draw(skinned(p) ? instance : world_[n] * instance, drawn_mesh, static_cast<int>(p));
      }
      degenerate_ += dropped;
    }
  }

  // False (and no draw) for a singular or non-finite world matrix.
  bool add_draw(const glm::dmat4& world, int mesh, int primitive) {
    const glm::dmat3 m3(world);
    const double det = glm::determinant(m3);
    if (!finite_matrix(world) || !std::isfinite(det) || det == 0.0) return false;
    Draw d;
    d.mesh = mesh;
    d.primitive = primitive;
    d.world = glm::mat4(world);
    d.normal_matrix = glm::mat3(glm::transpose(glm::inverse(m3)));
    d.mirrored = det < 0.0;
    const Primitive& p = scene_.meshes[mesh].primitives[primitive];
    world_bounds(d.world, p.bounds_min, p.bounds_max, d.world_bounds_min, d.world_bounds_max);
    scene_.draws.push_back(d);
    return true;
  }

  void place_camera(int n) {
    const glm::dmat4& world = world_[n];
    GltfCamera& c = scene_.cameras[data_.nodes[n].camera];
    glm::dvec3 forward = glm::dvec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    glm::dvec3 up = glm::dvec3(world * glm::dvec4(0.0, 1.0, 0.0, 0.0));
    if (!finite_matrix(world) || !usable_direction(forward)) fail(n, "places a camera");
    forward = glm::normalize(forward);
    up -= forward * glm::dot(forward, up);
    if (!usable_direction(up)) fail(n, "places a camera");
    c.position = glm::vec3(world[3]);
    c.forward = glm::vec3(forward);
    c.up = glm::vec3(glm::normalize(up));
  }

  void place_light(int n) {
    const glm::dmat4& world = world_[n];
    PunctualLight& l = scene_.lights[data_.nodes[n].light];
    const glm::dvec3 direction = glm::dvec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    if (!finite_matrix(world)) fail(n, "places a light");
    if (l.type == PunctualLight::Type::Spot && !usable_direction(direction)) fail(n, "places a spot light");
    l.position = glm::vec3(world[3]);
    if (usable_direction(direction)) l.direction = glm::vec3(glm::normalize(direction));
  }

  void place_sun(int n) {
    // The light shines along the node's -Z, so the sun lies along +Z.
    const glm::dvec3 to_sun = glm::dvec3(world_[n] * glm::dvec4(0.0, 0.0, 1.0, 0.0));
    if (!usable_direction(to_sun)) fail(n, "places the directional light (sun)");
    scene_.sun->direction_to_sun = glm::vec3(glm::normalize(to_sun));
  }

  Scene& scene_;
  const SceneAnimation& data_;
  const std::vector<glm::dmat4>& world_;
  std::string when_;
  size_t degenerate_ = 0;
};

void update_scene_bounds(Scene& scene) {
  scene.bounds_min = scene.bounds_max = glm::vec3(0.0f);
  if (scene.draws.empty()) return;
  scene.bounds_min = scene.draws[0].world_bounds_min;
  scene.bounds_max = scene.draws[0].world_bounds_max;
  for (const Draw& d : scene.draws) {
    scene.bounds_min = glm::min(scene.bounds_min, d.world_bounds_min);
    scene.bounds_max = glm::max(scene.bounds_max, d.world_bounds_max);
  }
}

std::string animation_names(const SceneAnimation* data) {
  if (!data || data->animations.empty()) return "none";
  std::string names;
  for (size_t i = 0; i < data->animations.size(); ++i) {
    const std::string& name = data->animations[i].name;
    names += (i ? ", " : "") + (name.empty() ? std::to_string(i) + " (unnamed)" : "\"" + name + "\"");
  }
  return names;
}

}  // namespace

glm::dmat4 NodeTransform::local() const {
  if (matrix) return *matrix;
  return glm::translate(glm::dmat4(1.0), translation) * glm::mat4_cast(rotation) * glm::scale(glm::dmat4(1.0), scale);
}

size_t pose_scene(Scene& scene, const SceneAnimation& animation_data, std::optional<size_t> animation, double time_s) {
  const std::vector<SceneNode>& nodes = animation_data.nodes;
  std::vector<NodeTransform> transforms(nodes.size());
  std::vector<std::vector<float>> weights(nodes.size());
  for (size_t n = 0; n < nodes.size(); ++n) {
    transforms[n] = nodes[n].rest;
    weights[n] = nodes[n].weights;
  }
  std::string when;
  if (animation) {
    const AnimationClip& clip = animation_data.animations.at(*animation);
    apply_animation(clip, time_s, transforms, weights);
    when = " (animation " + (clip.name.empty() ? std::to_string(*animation) : "'" + clip.name + "'") + " at " +
           std::to_string(time_s) + " s)";
  }
  std::vector<glm::dmat4> world(nodes.size());
  for (int n : animation_data.update_order) {
    const glm::dmat4 local = transforms[n].local();
    world[n] = nodes[n].parent < 0 ? local : world[nodes[n].parent] * local;
  }
  scene.draws.clear();
  PosePlacer placer(scene, animation_data, world, when);
  for (int n : animation_data.draw_order) placer.place(n, weights[n]);
  update_scene_bounds(scene);
  return placer.degenerate();
}

std::optional<size_t> described_animation(const Scene& scene, const SceneDescription& description) {
  if (!description.animation) return std::nullopt;
  const AnimationSpec& spec = *description.animation;
  const SceneAnimation* data = scene.animation.get();
  const size_t count = data ? data->animations.size() : 0;
  const std::string has = "'" + scene.source + "' has " + std::to_string(count) + " animation(s): " + animation_names(data);
  if (spec.index) {
    if (static_cast<size_t>(*spec.index) >= count) {
      throw InputError(description.path, "'animation.index' is " + std::to_string(*spec.index) + " but " + has);
    }
    return static_cast<size_t>(*spec.index);
  }
  for (size_t i = 0; i < count; ++i) {
    if (data->animations[i].name == spec.name) return i;
  }
  throw InputError(description.path, "'animation.name' is \"" + spec.name + "\" but " + has);
}

void pose_described_scene(Scene& scene, const SceneDescription& description) {
  if (std::optional<size_t> chosen = described_animation(scene, description)) {
    pose_scene(scene, *scene.animation, chosen, description.animation->time_s);
    scene.framing_min = scene.bounds_min;
    scene.framing_max = scene.bounds_max;
    return;
  }
  if (scene.animation && !scene.animation->animations.empty()) {
    std::cerr << scene.source << ": warning: the file has " << scene.animation->animations.size()
              << " animation(s) (" << animation_names(scene.animation.get())
              << "); the rest pose is shown (choose one with the scene key \"animation\")\n";
  }
}

}  // namespace cr

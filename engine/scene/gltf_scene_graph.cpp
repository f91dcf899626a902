#include "engine/scene/gltf_scene_graph.h"

#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/core/math_constants.h"
#include "engine/scene/gltf_animation.h"
#include "engine/scene/gltf_instancing.h"
#include "engine/scene/gltf_morph.h"
#include "engine/scene/gltf_skin.h"
#include "engine/scene/scene_animation.h"

namespace cr {

namespace {

bool all_finite(const std::vector<double>& v) {
  for (double d : v) {
    if (!std::isfinite(d)) return false;
  }
  return true;
}

NodeTransform node_transform(const GltfContext& ctx, const tinygltf::Node& n, size_t index) {
  std::string label = gltf_label("node", index, n.name);
  // Their sizes, and that a matrix comes without TRS, are checked on the JSON
  // (validate_gltf_schema): tinygltf drops the TRS of a node with a matrix.
  auto check = [&](const std::vector<double>& v, const char* name) {
    if (!all_finite(v)) ctx.fail(label + " " + name + " has a non-finite value");
  };
  check(n.matrix, "matrix");
  check(n.translation, "translation");
  check(n.rotation, "rotation");
  check(n.scale, "scale");
  NodeTransform t;
  if (!n.matrix.empty()) {
    t.matrix = glm::make_mat4(n.matrix.data());  // glTF matrices are column-major, like glm
    return t;
  }
  if (!n.translation.empty()) t.translation = glm::make_vec3(n.translation.data());
  if (!n.rotation.empty()) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF order is x, y, z, w
    double len = glm::length(q);
    if (!(len > 1e-6)) ctx.fail(label + " rotation is a zero quaternion");
    t.rotation = q / len;
  }
  if (!n.scale.empty()) t.scale = glm::make_vec3(n.scale.data());
  return t;
}

// The node's KHR_lights_punctual light index, or -1.
int node_light(const GltfContext& ctx, const tinygltf::Node& n, size_t index) {
  auto it = n.extensions.find("KHR_lights_punctual");
  if (it == n.extensions.end()) return -1;
  std::string label = gltf_label("node", index, n.name) + " KHR_lights_punctual";
  const tinygltf::Value& ext = it->second;
  if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsInt()) {
    ctx.fail(label + " must be an object with an integer \"light\"");
  }
  int light = ext.Get("light").GetNumberAsInt();
  if (light < 0 || static_cast<size_t>(light) >= ctx.model.lights.size()) {
    ctx.fail(label + " light " + std::to_string(light) + " out of range (" +
             std::to_string(ctx.model.lights.size()) + " lights)");
  }
  return light;
}

// `value[key]`, or a null value when `value` is not an object holding `key`.
const tinygltf::Value& member(const tinygltf::Value& value, const char* key) {
  static const tinygltf::Value kNone;
  return value.Has(key) ? value.Get(key) : kNone;
}

// Light `i` as written in the file: tinygltf reads an absent "range" and a
// "range" of 0 alike, and drops values of the wrong type.
const tinygltf::Value& light_json(const GltfContext& ctx, size_t i) {
  static const tinygltf::Value kNone;
  auto it = ctx.model.extensions.find("KHR_lights_punctual");
  if (it == ctx.model.extensions.end()) return kNone;
  const tinygltf::Value& lights = member(it->second, "lights");
  return i < lights.ArrayLen() ? lights.Get(static_cast<int>(i)) : kNone;
}

void validate_lights(const GltfContext& ctx) {
  for (size_t i = 0; i < ctx.model.lights.size(); ++i) {
    const tinygltf::Light& l = ctx.model.lights[i];
    const tinygltf::Value& json = light_json(ctx, i);
    std::string label = gltf_label("light", i, l.name);
    if (l.type != "directional" && l.type != "point" && l.type != "spot") {
      ctx.fail(label + " has unknown type \"" + l.type + "\"");
    }
    if ((json.Has("color") || !l.color.empty()) && (l.color.size() != 3 || !all_finite(l.color) || l.color[0] < 0 || l.color[1] < 0 || l.color[2] < 0)) {
      ctx.fail(label + " color must be 3 finite non-negative numbers");
    }
    if ((json.Has("intensity") && !member(json, "intensity").IsNumber()) || !std::isfinite(l.intensity) || l.intensity < 0) {
      ctx.fail(label + " intensity must be a finite number >= 0");
    }
    if (json.Has("range") && (!member(json, "range").IsNumber() || !std::isfinite(l.range) || !(l.range > 0.0))) {
      ctx.fail(label + " range must be a finite number > 0 (leave it out for an unlimited range)");
    }
    if (l.type == "spot") {
      const tinygltf::Value& spot = member(json, "spot");
      for (const char* key : {"innerConeAngle", "outerConeAngle"}) {
        if (spot.Has(key) && !member(spot, key).IsNumber()) ctx.fail(label + " spot." + key + " must be a number");
      }
      const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
      if (!std::isfinite(inner) || !std::isfinite(outer) || !(inner >= 0.0) || !(inner < outer) ||
          !(outer <= glm::half_pi<double>())) {
        ctx.fail(label + " spot cone angles (inner " + std::to_string(inner) + ", outer " + std::to_string(outer) +
                 ") must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
      }
    }
  }
}

// Checks node references, gives every node at most one parent and rejects
// cycles. Returns parent[node] (-1 for roots).
std::vector<int> validate_hierarchy(const GltfContext& ctx) {
  const tinygltf::Model& m = ctx.model;
  const size_t count = m.nodes.size();
  std::vector<int> parent(count, -1);
  for (size_t i = 0; i < count; ++i) {
    const tinygltf::Node& n = m.nodes[i];
    std::string label = gltf_label("node", i, n.name);
    if (n.mesh < -1 || (n.mesh >= 0 && static_cast<size_t>(n.mesh) >= m.meshes.size())) {
      ctx.fail(label + " mesh " + std::to_string(n.mesh) + " out of range (" + std::to_string(m.meshes.size()) + " meshes)");
    }
    if (n.camera < -1 || (n.camera >= 0 && static_cast<size_t>(n.camera) >= m.cameras.size())) {
      ctx.fail(label + " camera " + std::to_string(n.camera) + " out of range (" + std::to_string(m.cameras.size()) +
               " cameras)");
    }
    if (n.skin < -1 || (n.skin >= 0 && static_cast<size_t>(n.skin) >= m.skins.size())) {
      ctx.fail(label + " skin " + std::to_string(n.skin) + " out of range (" + std::to_string(m.skins.size()) + " skins)");
    }
    if (n.mesh < 0 && n.skin >= 0) ctx.fail(label + " has a skin but no mesh");
    if (n.mesh < 0 && !n.weights.empty()) ctx.fail(label + " has morph weights but no mesh");
    for (int c : n.children) {
      if (c < 0 || static_cast<size_t>(c) >= count) {
        ctx.fail(label + " child " + std::to_string(c) + " out of range (" + std::to_string(count) + " nodes)");
      }
      if (static_cast<size_t>(c) == i) ctx.fail(label + " lists itself as a child");
      if (parent[c] != -1) {
        ctx.fail("node " + std::to_string(c) + " has two parents (nodes " + std::to_string(parent[c]) + " and " +
                 std::to_string(i) + "); the node hierarchy must be a tree");
      }
      parent[c] = static_cast<int>(i);
    }
  }
  // With one parent each, a cycle is a parent chain that returns to itself.
  // Walk each chain once, marking nodes with the walk that first reached them.
  std::vector<size_t> walk(count, std::numeric_limits<size_t>::max());
  for (size_t start = 0; start < count; ++start) {
    int v = static_cast<int>(start);
    while (v != -1 && walk[v] == std::numeric_limits<size_t>::max()) {
      walk[v] = start;
      v = parent[v];
    }
    if (v != -1 && walk[v] == start) {
      ctx.fail("the node hierarchy has a cycle through node " + std::to_string(v) + "; it must be a tree");
    }
  }
  return parent;
}

std::vector<int> scene_roots(const GltfContext& ctx, const std::vector<int>& parent) {
  const tinygltf::Model& m = ctx.model;
  std::vector<int> roots;
  if (m.scenes.empty()) {
    if (m.defaultScene != -1) ctx.fail("scene " + std::to_string(m.defaultScene) + " out of range (no scenes)");
    for (size_t i = 0; i < parent.size(); ++i) {
      if (parent[i] == -1) roots.push_back(static_cast<int>(i));
    }
    return roots;
  }
  int s = m.defaultScene == -1 ? 0 : m.defaultScene;
  if (s < 0 || static_cast<size_t>(s) >= m.scenes.size()) {
    ctx.fail("scene " + std::to_string(s) + " out of range (" + std::to_string(m.scenes.size()) + " scenes)");
  }
  std::vector<bool> listed(parent.size(), false);
  for (int n : m.scenes[s].nodes) {
    std::string label = "scene " + std::to_string(s) + " node " + std::to_string(n);
    if (n < 0 || static_cast<size_t>(n) >= parent.size()) {
      ctx.fail(label + " out of range (" + std::to_string(parent.size()) + " nodes)");
    }
    if (parent[n] != -1) ctx.fail(label + " is not a root node (its parent is node " + std::to_string(parent[n]) + ")");
    if (listed[n]) ctx.fail(label + " is listed twice");
    listed[n] = true;
    roots.push_back(n);
  }
  return roots;
}

// The trees under `roots`, depth first, children in file order; an explicit
// stack, since a valid file may still nest nodes deeper than the call stack allows.
std::vector<int> depth_first(const GltfContext& ctx, const std::vector<int>& roots) {
  std::vector<int> order;
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int node = stack.back();
    stack.pop_back();
    order.push_back(node);
    const std::vector<int>& children = ctx.model.nodes[node].children;
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  return order;
}

// A camera's projection, checked; its node places it (pose_scene).
GltfCamera camera_projection(const GltfContext& ctx, int camera, size_t& negative_magnifications) {
  const tinygltf::Camera& c = ctx.model.cameras[camera];
  std::string label = gltf_label("camera", camera, c.name);
  GltfCamera out;
  out.name = c.name;
  if (c.type == "orthographic") {
    const tinygltf::OrthographicCamera& o = c.orthographic;
    if (!std::isfinite(o.xmag) || !std::isfinite(o.ymag) || o.xmag == 0.0 || o.ymag == 0.0) {
      ctx.fail(label + " xmag and ymag must be finite and non-zero");
    }
    if (!std::isfinite(o.znear) || o.znear < 0.0) ctx.fail(label + " znear must be finite and >= 0");
    if (!std::isfinite(o.zfar) || !(o.zfar > o.znear)) ctx.fail(label + " zfar must be finite and greater than znear");
    // Negative magnifications (which the spec advises against) would mirror
    // the view; their size is used.
    negative_magnifications += o.xmag < 0.0 || o.ymag < 0.0;
    out.orthographic = true;
    out.xmag = static_cast<float>(std::abs(o.xmag));
    out.ymag = static_cast<float>(std::abs(o.ymag));
    out.znear = static_cast<float>(o.znear);
    out.zfar = static_cast<float>(o.zfar);
    return out;
  }
  if (c.type != "perspective") ctx.fail(label + " has unknown type \"" + c.type + "\"");
  const tinygltf::PerspectiveCamera& p = c.perspective;
  if (!std::isfinite(p.yfov) || p.yfov <= 0.0 || p.yfov >= kPiD) ctx.fail(label + " yfov must be in (0, pi)");
  if (!std::isfinite(p.znear) || p.znear <= 0.0) ctx.fail(label + " znear must be finite and > 0");
  if (!std::isfinite(p.aspectRatio) || p.aspectRatio < 0.0) ctx.fail(label + " aspectRatio must be finite and > 0");
  // tinygltf reads an absent zfar (an infinite projection) as 0.
  if (!std::isfinite(p.zfar) || (p.zfar != 0.0 && !(p.zfar > p.znear))) {
    ctx.fail(label + " zfar must be finite and greater than znear");
  }
  out.yfov_rad = static_cast<float>(p.yfov);
  out.znear = static_cast<float>(p.znear);
  if (p.aspectRatio > 0.0) out.aspect = static_cast<float>(p.aspectRatio);
  return out;
}

glm::vec3 light_color(const tinygltf::Light& l) {
  return l.color.empty() ? glm::vec3(1.0f) : glm::vec3(l.color[0], l.color[1], l.color[2]);
}

PunctualLight punctual_light(const tinygltf::Light& l) {
  PunctualLight out;
  out.type = l.type == "spot" ? PunctualLight::Type::Spot : PunctualLight::Type::Point;
  out.name = l.name;
  out.color = light_color(l);
  out.intensity = static_cast<float>(l.intensity);
  out.range = static_cast<float>(l.range);
  if (out.type == PunctualLight::Type::Spot) {
    out.inner_cone_rad = static_cast<float>(l.spot.innerConeAngle);
    out.outer_cone_rad = static_cast<float>(l.spot.outerConeAngle);
  }
  return out;
}

// The node table of `anim` for every glTF node: rest transforms, meshes with
// their morph weights, instances and skins.
class NodeTable {
 public:
  NodeTable(const GltfContext& ctx, const std::vector<int>& parent, SceneAnimation& anim)
      : ctx_(ctx), anim_(anim) {
    anim.nodes.resize(ctx.model.nodes.size());
    for (size_t i = 0; i < anim.nodes.size(); ++i) {
      const tinygltf::Node& n = ctx.model.nodes[i];
      SceneNode& node = anim.nodes[i];
      node.name = n.name;
      node.parent = parent[i];
      node.rest = node_transform(ctx, n, i);
      if (n.mesh >= 0) {
        add_mesh(i);
      } else if (n.extensions.count("EXT_mesh_gpu_instancing")) {
        ++instancing_without_mesh_;
      }
    }
  }

  void report() const {
    if (instancing_without_mesh_ > 0) {
      ctx_.warn(std::to_string(instancing_without_mesh_) + " node(s) without a mesh have EXT_mesh_gpu_instancing; ignored");
    }
    if (unskinned_primitives_ > 0) {
      ctx_.warn(std::to_string(unskinned_primitives_) + " primitive(s) of skinned nodes have no JOINTS_0/WEIGHTS_0; "
                "drawn unskinned, placed by their node");
    }
  }

 private:
  void add_mesh(size_t i) {
    const tinygltf::Node& n = ctx_.model.nodes[i];
    SceneNode& node = anim_.nodes[i];
    node.mesh = n.mesh;
    const MeshDeformation& deformation = anim_.deformations[n.mesh];
    node.weights = rest_morph_weights(ctx_, i, deformation.target_count);
    node.instances = load_instances(ctx_, i);
    if (n.skin < 0) return;
    const SceneSkin& skin = anim_.skins[n.skin];
    for (size_t p = 0; p < deformation.primitives.size(); ++p) {
      const PrimitiveDeformation& d = deformation.primitives[p];
      if (!d.skinnable()) {
        ++unskinned_primitives_;
        continue;
      }
      if (d.max_joint >= skin.joints.size()) {
        ctx_.fail(gltf_label("node", i, n.name) + " mesh " + std::to_string(n.mesh) + " primitive " + std::to_string(p) +
                  " uses joint " + std::to_string(d.max_joint) + " but its skin " + std::to_string(n.skin) + " has " +
                  std::to_string(skin.joints.size()) + " joints");
      }
      node.skin = n.skin;
    }
  }

  const GltfContext& ctx_;
  SceneAnimation& anim_;
  size_t instancing_without_mesh_ = 0;
  size_t unskinned_primitives_ = 0;
};

// Gives every node the scene draws its camera, light or sun, in draw order.
class NodeRoles {
 public:
  NodeRoles(const GltfContext& ctx, SceneAnimation& anim, Scene& scene) : ctx_(ctx) {
    for (int n : anim.draw_order) {
      const tinygltf::Node& src = ctx.model.nodes[n];
      SceneNode& node = anim.nodes[n];
      if (src.camera >= 0) {
        node.camera = static_cast<int>(scene.cameras.size());
        scene.cameras.push_back(camera_projection(ctx, src.camera, negative_magnifications_));
      }
      const int light = node_light(ctx, src, n);
      if (light < 0) continue;
      const tinygltf::Light& l = ctx.model.lights[light];
      if (l.type != "directional") {
        node.light = static_cast<int>(scene.lights.size());
        scene.lights.push_back(punctual_light(l));
      } else if (scene.sun) {
        ++ignored_directional_;
      } else {
        GltfSun sun;
        sun.color = light_color(l);
        sun.intensity = static_cast<float>(l.intensity);
        scene.sun = sun;
        node.sun = true;
      }
    }
  }

  void report() const {
    if (negative_magnifications_ > 0) {
      ctx_.warn(std::to_string(negative_magnifications_) + " orthographic camera(s) have a negative xmag or ymag; "
                "their absolute values are used (the view is not mirrored)");
    }
    if (ignored_directional_ > 0) {
      ctx_.warn(std::to_string(ignored_directional_) + " directional light(s) ignored (only the first is used, as the sun)");
    }
  }

 private:
  const GltfContext& ctx_;
  size_t negative_magnifications_ = 0;
  size_t ignored_directional_ = 0;
};

// Gives every drawn node whose shape is not its mesh's rest shape (skinned,
// morphed by non-zero or animated weights) a mesh of its own in the scene.
void add_posed_meshes(SceneAnimation& anim, Scene& scene) {
  std::set<int> animated_weights;
  for (const AnimationClip& clip : anim.animations) {
    for (const AnimationChannel& c : clip.channels) {
      if (c.path == AnimationPath::Weights) animated_weights.insert(c.node);
    }
  }
  for (int n : anim.draw_order) {
    SceneNode& node = anim.nodes[n];
    if (node.mesh < 0) continue;
    bool morphed = animated_weights.count(n) > 0;
    for (float w : node.weights) morphed = morphed || w != 0.0f;
    if (node.skin < 0 && !morphed) continue;
    node.posed_mesh = static_cast<int>(scene.meshes.size());
    Mesh copy = scene.meshes[node.mesh];
    scene.meshes.push_back(std::move(copy));
  }
}

}  // namespace

void place_nodes(const GltfContext& ctx, GltfMeshes& meshes, Scene& scene) {
  validate_lights(ctx);
  const std::vector<int> parent = validate_hierarchy(ctx);
  SceneAnimation anim;
  anim.deformations = std::move(meshes.deformations);
  anim.skins = load_skins(ctx, parent);
  NodeTable table(ctx, parent, anim);
  std::vector<int> tree_roots;
  for (size_t i = 0; i < parent.size(); ++i) {
    if (parent[i] == -1) tree_roots.push_back(static_cast<int>(i));
  }
  anim.update_order = depth_first(ctx, tree_roots);
  anim.draw_order = depth_first(ctx, scene_roots(ctx, parent));
  NodeRoles roles(ctx, anim, scene);
  anim.animations = load_animations(ctx, anim.nodes, anim.deformations);
  add_posed_meshes(anim, scene);

  const size_t degenerate = pose_scene(scene, anim, std::nullopt, 0.0);
  scene.framing_min = scene.bounds_min;
  scene.framing_max = scene.bounds_max;
  table.report();
  roles.report();
  if (degenerate > 0) {
    ctx.warn(std::to_string(degenerate) + " node(s) or instance(s) with a singular or non-finite world matrix are not drawn");
  }
  if (!anim.animations.empty()) scene.animation = std::make_shared<const SceneAnimation>(std::move(anim));
}

}  // namespace cr

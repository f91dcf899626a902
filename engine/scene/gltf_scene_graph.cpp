#include "engine/scene/gltf_scene_graph.h"

#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace cr {

namespace {

bool all_finite(const std::vector<double>& v) {
  for (double d : v) {
    if (!std::isfinite(d)) return false;
  }
  return true;
}

glm::dmat4 local_matrix(const GltfContext& ctx, const tinygltf::Node& n, size_t index) {
  std::string label = gltf_label("node", index, n.name);
  auto check = [&](const std::vector<double>& v, size_t size, const char* name) {
    if (!v.empty() && v.size() != size) {
      ctx.fail(label + " " + name + " has " + std::to_string(v.size()) + " values; expected " + std::to_string(size));
    }
    if (!all_finite(v)) ctx.fail(label + " " + name + " has a non-finite value");
  };
  check(n.matrix, 16, "matrix");
  check(n.translation, 3, "translation");
  check(n.rotation, 4, "rotation");
  check(n.scale, 3, "scale");
  if (!n.matrix.empty()) {
    if (!n.translation.empty() || !n.rotation.empty() || !n.scale.empty()) {
      ctx.fail(label + " has both matrix and translation/rotation/scale");
    }
    return glm::make_mat4(n.matrix.data());  // glTF matrices are column-major, like glm
  }
  glm::dmat4 m(1.0);
  if (!n.translation.empty()) m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (!n.rotation.empty()) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF order is x, y, z, w
    double len = glm::length(q);
    if (!(len > 1e-6)) ctx.fail(label + " rotation is a zero quaternion");
    m *= glm::mat4_cast(q / len);
  }
  if (!n.scale.empty()) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return m;
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

void validate_lights(const GltfContext& ctx) {
  for (size_t i = 0; i < ctx.model.lights.size(); ++i) {
    const tinygltf::Light& l = ctx.model.lights[i];
    std::string label = gltf_label("light", i, l.name);
    if (l.type != "directional" && l.type != "point" && l.type != "spot") {
      ctx.fail(label + " has unknown type \"" + l.type + "\"");
    }
    if (!l.color.empty() && (l.color.size() != 3 || !all_finite(l.color) || l.color[0] < 0 || l.color[1] < 0 || l.color[2] < 0)) {
      ctx.fail(label + " color must be 3 finite non-negative numbers");
    }
    if (!std::isfinite(l.intensity) || l.intensity < 0) ctx.fail(label + " intensity must be finite and >= 0");
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

void expand_bounds(const glm::mat4& world, const glm::vec3& lo, const glm::vec3& hi, glm::vec3& out_lo,
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

class NodePlacer {
 public:
  NodePlacer(const GltfContext& ctx, const GltfMeshes& meshes, Scene& scene)
      : ctx_(ctx), meshes_(meshes), scene_(scene) {}

  void place(int node, const glm::dmat4& world) {
    const tinygltf::Node& n = ctx_.model.nodes[node];
    if (n.mesh >= 0) add_draws(n.mesh, world);
    if (n.camera >= 0) add_camera(n.camera, world);
    int light = node_light(ctx_, n, node);
    if (light >= 0) add_light(light, world);
  }

  void report() const {
    if (degenerate_nodes_ > 0) {
      ctx_.warn(std::to_string(degenerate_nodes_) + " node(s) with a singular or non-finite world matrix are not drawn");
    }
    if (ignored_cameras_ > 0) ctx_.warn(std::to_string(ignored_cameras_) + " orthographic camera(s) ignored");
    if (ignored_lights_ > 0) {
      ctx_.warn(std::to_string(ignored_lights_) + " punctual light(s) ignored (only the first directional light is used, as the sun)");
    }
  }

 private:
  void add_draws(int mesh, const glm::dmat4& world) {
    glm::dmat3 m3(world);
    double det = glm::determinant(m3);
    bool finite_world = true;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) finite_world = finite_world && std::isfinite(world[c][r]);
    }
    if (!finite_world || !std::isfinite(det) || det == 0.0) {
      ++degenerate_nodes_;
      return;
    }
    const std::vector<int>& index = meshes_.primitive_index[mesh];
    for (int prim : index) {
      if (prim < 0) continue;
      Draw d;
      d.mesh = mesh;
      d.primitive = prim;
      d.world = glm::mat4(world);
      d.normal_matrix = glm::mat3(glm::transpose(glm::inverse(m3)));
      d.mirrored = det < 0.0;
      const Primitive& p = scene_.meshes[mesh].primitives[prim];
      expand_bounds(d.world, p.bounds_min, p.bounds_max, d.world_bounds_min, d.world_bounds_max);
      scene_.draws.push_back(d);
    }
  }

  void add_camera(int camera, const glm::dmat4& world) {
    const tinygltf::Camera& c = ctx_.model.cameras[camera];
    std::string label = gltf_label("camera", camera, c.name);
    if (c.type == "orthographic") {
      ++ignored_cameras_;
      return;
    }
    if (c.type != "perspective") ctx_.fail(label + " has unknown type \"" + c.type + "\"");
    const tinygltf::PerspectiveCamera& p = c.perspective;
    if (!std::isfinite(p.yfov) || p.yfov <= 0.0 || p.yfov >= glm::pi<double>()) ctx_.fail(label + " yfov must be in (0, pi)");
    if (!std::isfinite(p.znear) || p.znear <= 0.0) ctx_.fail(label + " znear must be finite and > 0");
    if (!std::isfinite(p.aspectRatio) || p.aspectRatio < 0.0) ctx_.fail(label + " aspectRatio must be finite and > 0");
    GltfCamera out;
    out.name = c.name;
    out.position = glm::vec3(world[3]);
    glm::dvec3 forward = glm::dvec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    glm::dvec3 up = glm::dvec3(world * glm::dvec4(0.0, 1.0, 0.0, 0.0));
    double flen = glm::length(forward);
    if (!(flen > 0.0) || !std::isfinite(flen)) ctx_.fail(label + " is placed by a degenerate node transform");
    forward /= flen;
    up -= forward * glm::dot(forward, up);
    double ulen = glm::length(up);
    if (!(ulen > 0.0) || !std::isfinite(ulen)) ctx_.fail(label + " is placed by a degenerate node transform");
    out.forward = glm::vec3(forward);
    out.up = glm::vec3(up / ulen);
    out.yfov_rad = static_cast<float>(p.yfov);
    out.znear = static_cast<float>(p.znear);
    if (p.aspectRatio > 0.0) out.aspect = static_cast<float>(p.aspectRatio);
    scene_.cameras.push_back(out);
  }

  void add_light(int light, const glm::dmat4& world) {
    const tinygltf::Light& l = ctx_.model.lights[light];
    if (l.type != "directional" || scene_.sun) {
      ++ignored_lights_;
      return;
    }
    // The light shines along the node's -Z, so the sun lies along +Z.
    glm::dvec3 to_sun = glm::dvec3(world * glm::dvec4(0.0, 0.0, 1.0, 0.0));
    double len = glm::length(to_sun);
    if (!(len > 0.0) || !std::isfinite(len)) {
      ctx_.fail(gltf_label("light", light, l.name) + " is placed by a degenerate node transform");
    }
    GltfSun sun;
    sun.direction_to_sun = glm::vec3(to_sun / len);
    if (!l.color.empty()) sun.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
    sun.intensity = static_cast<float>(l.intensity);
    scene_.sun = sun;
  }

  const GltfContext& ctx_;
  const GltfMeshes& meshes_;
  Scene& scene_;
  size_t degenerate_nodes_ = 0;
  size_t ignored_cameras_ = 0;
  size_t ignored_lights_ = 0;
};

}  // namespace

void place_nodes(const GltfContext& ctx, const GltfMeshes& meshes, Scene& scene) {
  validate_lights(ctx);
  std::vector<int> parent = validate_hierarchy(ctx);
  std::vector<glm::dmat4> local(ctx.model.nodes.size());
  for (size_t i = 0; i < local.size(); ++i) local[i] = local_matrix(ctx, ctx.model.nodes[i], i);

  NodePlacer placer(ctx, meshes, scene);
  // Depth first, children in file order; an explicit stack, since a valid
  // file may still nest nodes deeper than the call stack allows.
  std::vector<std::pair<int, glm::dmat4>> stack;
  std::vector<int> roots = scene_roots(ctx, parent);
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, local[*it]);
  while (!stack.empty()) {
    auto [node, world] = stack.back();
    stack.pop_back();
    placer.place(node, world);
    const std::vector<int>& children = ctx.model.nodes[node].children;
    for (auto it = children.rbegin(); it != children.rend(); ++it) stack.emplace_back(*it, world * local[*it]);
  }
  placer.report();

  if (!scene.draws.empty()) {
    scene.bounds_min = scene.draws[0].world_bounds_min;
    scene.bounds_max = scene.draws[0].world_bounds_max;
    for (const Draw& d : scene.draws) {
      scene.bounds_min = glm::min(scene.bounds_min, d.world_bounds_min);
      scene.bounds_max = glm::max(scene.bounds_max, d.world_bounds_max);
    }
  }
}

}  // namespace cr

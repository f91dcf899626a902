#include "engine/scene/gltf_morph.h"

#include <cmath>
#include <map>

#include "engine/scene/gltf_accessors.h"

namespace cr {

namespace {

std::vector<glm::vec3> read_deltas(const GltfContext& ctx, int accessor, size_t vertex_count, const std::string& what) {
  const FloatAccessor a = read_float_accessor(ctx, accessor, what, {TINYGLTF_TYPE_VEC3}, AttributeKind::MorphDelta);
  if (a.count != vertex_count) {
    ctx.fail(what + " has " + std::to_string(a.count) + " elements but POSITION has " + std::to_string(vertex_count));
  }
  std::vector<glm::vec3> out(a.count);
  for (size_t v = 0; v < a.count; ++v) {
    out[v] = glm::vec3(a.values[3 * v], a.values[3 * v + 1], a.values[3 * v + 2]);
    if (!std::isfinite(out[v].x) || !std::isfinite(out[v].y) || !std::isfinite(out[v].z)) {
      ctx.fail(what + ": vertex " + std::to_string(v) + " is not finite (NaN or Inf)");
    }
  }
  return out;
}

std::vector<float> checked_weights(const GltfContext& ctx, const std::vector<double>& weights, size_t target_count,
                                   const std::string& label) {
  if (weights.size() != target_count) {
    ctx.fail(label + " weights has " + std::to_string(weights.size()) + " values but its mesh has " +
             std::to_string(target_count) + " morph targets");
  }
  std::vector<float> out(weights.size());
  for (size_t i = 0; i < weights.size(); ++i) {
    out[i] = static_cast<float>(weights[i]);
    if (!std::isfinite(out[i])) ctx.fail(label + " weights[" + std::to_string(i) + "] is not finite");
  }
  return out;
}

}  // namespace

MorphTargets load_morph_targets(const GltfContext& ctx, const tinygltf::Primitive& primitive, size_t vertex_count,
                                const std::string& label) {
  MorphTargets out;
  for (size_t t = 0; t < primitive.targets.size(); ++t) {
    MorphTarget target;
    for (const auto& [name, accessor] : primitive.targets[t]) {
      const std::string what = label + " target " + std::to_string(t) + " " + name;
      if (name == "POSITION") {
        target.positions = read_deltas(ctx, accessor, vertex_count, what);
      } else if (name == "NORMAL") {
        target.normals = read_deltas(ctx, accessor, vertex_count, what);
      } else if (name == "TANGENT") {
        target.tangents = read_deltas(ctx, accessor, vertex_count, what);
      } else {
        check_accessor(ctx, accessor, what);
        ++out.ignored_attributes;
      }
    }
    out.targets.push_back(std::move(target));
  }
  return out;
}

size_t mesh_target_count(const GltfContext& ctx, size_t mesh) {
  const tinygltf::Mesh& m = ctx.model.meshes[mesh];
  const std::string label = gltf_label("mesh", mesh, m.name);
  const size_t count = m.primitives.empty() ? 0 : m.primitives[0].targets.size();
  for (size_t p = 0; p < m.primitives.size(); ++p) {
    const std::vector<std::map<std::string, int>>& targets = m.primitives[p].targets;
    if (targets.size() != count) {
      ctx.fail(label + " primitive " + std::to_string(p) + " has " + std::to_string(targets.size()) +
               " morph targets but primitive 0 has " + std::to_string(count) + " (all primitives must have the same)");
    }
    // Every primitive's, drawn or not: load_morph_targets reads only those
    // of the primitives that are drawn (not points or lines).
    for (size_t t = 0; t < targets.size(); ++t) {
      for (const auto& [name, accessor] : targets[t]) {
        check_accessor(ctx, accessor, label + " primitive " + std::to_string(p) + " target " + std::to_string(t) + " " + name);
      }
    }
  }
  if (!m.weights.empty()) checked_weights(ctx, m.weights, count, label);
  return count;
}

std::vector<float> rest_morph_weights(const GltfContext& ctx, size_t node, size_t target_count) {
  const tinygltf::Node& n = ctx.model.nodes[node];
  if (!n.weights.empty()) return checked_weights(ctx, n.weights, target_count, gltf_label("node", node, n.name));
  const tinygltf::Mesh& m = ctx.model.meshes[n.mesh];
  if (!m.weights.empty()) return checked_weights(ctx, m.weights, target_count, gltf_label("mesh", n.mesh, m.name));
  return std::vector<float>(target_count, 0.0f);
}

}  // namespace cr

#include "engine/scene/gltf_skin.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "engine/scene/gltf_accessors.h"

namespace cr {

namespace {

// Accepted deviation of a vertex's weight sum from 1: quantized weights
// (UNSIGNED_BYTE) round each of up to 8 influences by 1/510.
constexpr double kWeightSumTolerance = 0.02;

bool is_ancestor_or_self(const std::vector<int>& parent, int ancestor, int node) {
  for (int n = node; n != -1; n = parent[n]) {
    if (n == ancestor) return true;
  }
  return false;
}

}  // namespace

void load_skin_influences(const GltfContext& ctx, const tinygltf::Primitive& primitive, size_t vertex_count,
                          const std::string& label, PrimitiveDeformation& deformation) {
  for (int set = 0;; ++set) {
    const std::string joints_name = "JOINTS_" + std::to_string(set);
    const std::string weights_name = "WEIGHTS_" + std::to_string(set);
    auto joints = primitive.attributes.find(joints_name);
    auto weights = primitive.attributes.find(weights_name);
    if (joints == primitive.attributes.end() && weights == primitive.attributes.end()) break;
    if (joints == primitive.attributes.end() || weights == primitive.attributes.end()) {
      ctx.fail(label + " has " + (joints == primitive.attributes.end() ? weights_name + " but no " + joints_name
                                                                       : joints_name + " but no " + weights_name));
    }
    std::vector<glm::u16vec4> j = read_joints_accessor(ctx, joints->second, label + " attribute " + joints_name);
    const FloatAccessor w = read_float_accessor(ctx, weights->second, label + " attribute " + weights_name,
                                                {TINYGLTF_TYPE_VEC4}, AttributeKind::Weights);
    if (j.size() != vertex_count || w.count != vertex_count) {
      ctx.fail(label + " " + joints_name + "/" + weights_name + " have " + std::to_string(j.size()) + "/" +
               std::to_string(w.count) + " elements but POSITION has " + std::to_string(vertex_count));
    }
    std::vector<glm::vec4> wv(vertex_count);
    for (size_t v = 0; v < vertex_count; ++v) {
      wv[v] = glm::make_vec4(&w.values[4 * v]);
      for (int k = 0; k < 4; ++k) {
        deformation.max_joint = std::max<uint32_t>(deformation.max_joint, j[v][k]);
        if (!std::isfinite(wv[v][k]) || wv[v][k] < 0.0f) {
          ctx.fail(label + " attribute " + weights_name + ": vertex " + std::to_string(v) +
                   " has a negative or non-finite weight");
        }
      }
    }
    deformation.joints.push_back(std::move(j));
    deformation.weights.push_back(std::move(wv));
  }
  if (deformation.joints.empty()) return;
  for (size_t v = 0; v < vertex_count; ++v) {
    double sum = 0.0;
    for (const std::vector<glm::vec4>& set : deformation.weights) sum += double(set[v].x) + set[v].y + set[v].z + set[v].w;
    if (!(std::abs(sum - 1.0) <= kWeightSumTolerance)) {
      ctx.fail(label + " skin weights of vertex " + std::to_string(v) + " sum to " + std::to_string(sum) +
               "; they must sum to 1");
    }
    for (std::vector<glm::vec4>& set : deformation.weights) set[v] = glm::vec4(glm::dvec4(set[v]) / sum);
  }
}

std::vector<SceneSkin> load_skins(const GltfContext& ctx, const std::vector<int>& parent) {
  const tinygltf::Model& m = ctx.model;
  std::vector<SceneSkin> skins;
  size_t loose_skeletons = 0;
  for (size_t s = 0; s < m.skins.size(); ++s) {
    const tinygltf::Skin& src = m.skins[s];
    const std::string label = gltf_label("skin", s, src.name);
    if (src.joints.empty()) ctx.fail(label + " has no joints");
    std::vector<bool> used(m.nodes.size(), false);
    for (int j : src.joints) {
      if (j < 0 || static_cast<size_t>(j) >= m.nodes.size()) {
        ctx.fail(label + " joint " + std::to_string(j) + " out of range (" + std::to_string(m.nodes.size()) + " nodes)");
      }
      if (used[j]) ctx.fail(label + " lists node " + std::to_string(j) + " twice as a joint");
      used[j] = true;
    }
    if (src.skeleton != -1) {
      if (src.skeleton < 0 || static_cast<size_t>(src.skeleton) >= m.nodes.size()) {
        ctx.fail(label + " skeleton " + std::to_string(src.skeleton) + " out of range (" +
                 std::to_string(m.nodes.size()) + " nodes)");
      }
      bool common_root = std::all_of(src.joints.begin(), src.joints.end(),
                                     [&](int j) { return is_ancestor_or_self(parent, src.skeleton, j); });
      loose_skeletons += !common_root;
    }
    SceneSkin skin;
    skin.name = src.name;
    skin.joints = src.joints;
    skin.inverse_bind.assign(src.joints.size(), glm::dmat4(1.0));
    if (src.inverseBindMatrices != -1) {
      const std::string what = label + " inverseBindMatrices";
      const FloatAccessor ibm = read_float_accessor(ctx, src.inverseBindMatrices, what, {TINYGLTF_TYPE_MAT4},
                                                    AttributeKind::Scalar);
      if (ibm.count < src.joints.size()) {
        ctx.fail(what + " has " + std::to_string(ibm.count) + " matrices for " + std::to_string(src.joints.size()) +
                 " joints");
      }
      for (size_t j = 0; j < src.joints.size(); ++j) {
        for (size_t k = 0; k < 16; ++k) {
          if (!std::isfinite(ibm.values[16 * j + k])) ctx.fail(what + ": matrix " + std::to_string(j) + " is not finite");
        }
        skin.inverse_bind[j] = glm::dmat4(glm::make_mat4(&ibm.values[16 * j]));  // column-major, like glm
      }
    }
    skins.push_back(std::move(skin));
  }
  if (loose_skeletons > 0) {
    ctx.warn(std::to_string(loose_skeletons) + " skin(s) name a skeleton that is not a common root of their joints; "
             "ignored (the skeleton does not change the pose)");
  }
  return skins;
}

}  // namespace cr

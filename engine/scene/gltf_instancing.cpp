#include "engine/scene/gltf_instancing.h"

#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/gltf_accessors.h"

namespace cr {

std::vector<glm::dmat4> load_instances(const GltfContext& ctx, size_t node) {
  const tinygltf::Node& n = ctx.model.nodes[node];
  auto it = n.extensions.find("EXT_mesh_gpu_instancing");
  if (it == n.extensions.end()) return {};
  const std::string label = gltf_label("node", node, n.name) + " EXT_mesh_gpu_instancing";
  const tinygltf::Value& ext = it->second;
  // tinygltf reads an empty JSON object as a null value.
  if (!ext.Has("attributes") || ext.Get("attributes").Keys().empty()) {
    ctx.fail(label + " must have a non-empty object \"attributes\"");
  }
  const tinygltf::Value& attributes = ext.Get("attributes");
  FloatAccessor translation, rotation, scale;
  std::optional<size_t> count;
  std::string first;
  for (const std::string& name : attributes.Keys()) {
    const tinygltf::Value& index = attributes.Get(name);
    const std::string what = label + " attribute " + name;
    if (!index.IsInt() || index.GetNumberAsInt() < 0) ctx.fail(what + " must be an accessor index");
    const int accessor = index.GetNumberAsInt();
    size_t c = 0;
    if (name == "TRANSLATION") {
      translation = read_float_accessor(ctx, accessor, what, {TINYGLTF_TYPE_VEC3}, AttributeKind::Scalar);
      c = translation.count;
    } else if (name == "ROTATION") {
      // The extension allows FLOAT and normalized BYTE/SHORT: the component
      // types of a quantized TANGENT.
      rotation = read_float_accessor(ctx, accessor, what, {TINYGLTF_TYPE_VEC4}, AttributeKind::Tangent);
      c = rotation.count;
    } else if (name == "SCALE") {
      scale = read_float_accessor(ctx, accessor, what, {TINYGLTF_TYPE_VEC3}, AttributeKind::Scalar);
      c = scale.count;
    } else if (name.rfind('_', 0) == 0) {
      c = check_accessor(ctx, accessor, what);  // application-specific: not used, but must be sound
    } else {
      ctx.fail(what + " is not TRANSLATION, ROTATION, SCALE or an application-specific \"_NAME\"");
    }
    if (count && *count != c) {
      ctx.fail(what + " has " + std::to_string(c) + " elements but " + first + " has " + std::to_string(*count) +
               " (all must have the same count)");
    }
    count = c;
    if (first.empty()) first = name;
  }
  std::vector<glm::dmat4> instances(*count);
  for (size_t i = 0; i < *count; ++i) {
    const std::string what = label + " instance " + std::to_string(i);
    glm::dmat4 m(1.0);
    if (translation.count) {
      const glm::dvec3 t(translation.values[3 * i], translation.values[3 * i + 1], translation.values[3 * i + 2]);
      if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) ctx.fail(what + " TRANSLATION is not finite");
      m = glm::translate(m, t);
    }
    if (rotation.count) {
      const float* r = &rotation.values[4 * i];
      const glm::dquat q(r[3], r[0], r[1], r[2]);  // glTF order is x, y, z, w
      const double len = glm::length(q);
      if (!std::isfinite(len) || !(len > 1e-6)) ctx.fail(what + " ROTATION is not a finite non-zero quaternion");
      m *= glm::mat4_cast(q / len);
    }
    if (scale.count) {
      const glm::dvec3 s(scale.values[3 * i], scale.values[3 * i + 1], scale.values[3 * i + 2]);
      if (!std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(s.z)) ctx.fail(what + " SCALE is not finite");
      m = glm::scale(m, s);
    }
    instances[i] = m;
  }
  return instances;
}

}  // namespace cr

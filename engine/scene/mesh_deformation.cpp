#include "engine/scene/mesh_deformation.h"

#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>

#include "engine/scene/mesh_generation.h"

namespace cr {

namespace {

bool usable(const glm::dvec3& v) {
  const double len = glm::length(v);
  return std::isfinite(len) && len > 1e-12;
}

// The weighted sum of a vertex's joint matrices.
glm::dmat4 blended_joint_matrix(const PrimitiveDeformation& d, size_t vertex, const std::vector<glm::dmat4>& joints) {
  glm::dmat4 m(0.0);
  for (size_t set = 0; set < d.joints.size(); ++set) {
    const glm::u16vec4& j = d.joints[set][vertex];
    const glm::vec4& w = d.weights[set][vertex];
    for (int k = 0; k < 4; ++k) {
      if (w[k] != 0.0f) m += double(w[k]) * joints[j[k]];
    }
  }
  return m;
}

}  // namespace

void deform_primitive(const Primitive& rest, const PrimitiveDeformation& deformation,
                      const std::vector<float>& weights, const std::vector<glm::dmat4>& joint_matrices,
                      Primitive& out) {
  const bool skinned = !joint_matrices.empty();
  const bool tangents = !rest.tangents.empty() && !deformation.generated_tangents;
  for (size_t v = 0; v < rest.positions.size(); ++v) {
    // Morph in float, in target order: exactly rest + sum(w_i * delta_i).
    glm::vec3 p = rest.positions[v];
    glm::vec3 n = rest.normals[v];
    glm::vec3 t = tangents ? glm::vec3(rest.tangents[v]) : glm::vec3(0.0f);
    for (size_t i = 0; i < deformation.targets.size(); ++i) {
      const float w = weights[i];
      if (w == 0.0f) continue;
      const MorphTarget& target = deformation.targets[i];
      if (!target.positions.empty()) p += w * target.positions[v];
      if (!target.normals.empty()) n += w * target.normals[v];
      if (tangents && !target.tangents.empty()) t += w * target.tangents[v];
    }
    glm::dvec3 pn(n), pt(t);
    if (skinned) {
      const glm::dmat4 m = blended_joint_matrix(deformation, v, joint_matrices);
      const glm::dmat3 m3(m);
      p = glm::vec3(m * glm::dvec4(p, 1.0));
      // A singular blend (joints scaled to zero) collapses the vertex; its
      // unskinned normal is kept, as no visible surface depends on it.
      const glm::dvec3 skinned_n = glm::inverseTranspose(m3) * pn;
      if (usable(skinned_n)) pn = skinned_n;
      pt = m3 * pt;
    }
    out.positions[v] = p;
    // Morph deltas may cancel a normal; the rest normal stands in for it.
    out.normals[v] = usable(pn) ? glm::vec3(glm::normalize(pn)) : rest.normals[v];
    if (tangents) {
      const glm::dvec3 unit_n(out.normals[v]);
      const glm::dvec3 ortho = pt - unit_n * glm::dot(unit_n, pt);
      const glm::vec3 xyz = usable(ortho) ? glm::vec3(glm::normalize(ortho)) : any_orthogonal(out.normals[v]);
      out.tangents[v] = glm::vec4(xyz, rest.tangents[v].w);
    }
  }
  if (deformation.flat_normals) out.normals = generate_normals(out.positions, out.indices);
  if (deformation.generated_tangents) {
    const std::vector<glm::vec2>& uv = deformation.tangent_texcoord == 1 ? out.texcoords1 : out.texcoords;
    out.tangents = generate_tangents(out.positions, out.normals, uv, out.indices);
  }
  out.bounds_min = out.bounds_max = out.positions[0];
  for (const glm::vec3& p : out.positions) {
    out.bounds_min = glm::min(out.bounds_min, p);
    out.bounds_max = glm::max(out.bounds_max, p);
  }
}

}  // namespace cr

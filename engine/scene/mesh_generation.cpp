#include "engine/scene/mesh_generation.h"

#include <cmath>

namespace cr {

std::vector<uint32_t> triangulate_strip(const std::vector<uint32_t>& strip) {
  std::vector<uint32_t> out;
  if (strip.size() < 3) return out;
  out.reserve(3 * (strip.size() - 2));
  for (size_t i = 0; i + 2 < strip.size(); ++i) {
    // Odd triangles swap their last two vertices so every triangle keeps the
    // strip's winding: {v_i, v_(i+1+i%2), v_(i+2-i%2)}.
    out.push_back(strip[i]);
    out.push_back(strip[i + 1 + i % 2]);
    out.push_back(strip[i + 2 - i % 2]);
  }
  return out;
}

std::vector<uint32_t> triangulate_fan(const std::vector<uint32_t>& fan) {
  std::vector<uint32_t> out;
  if (fan.size() < 3) return out;
  out.reserve(3 * (fan.size() - 2));
  for (size_t i = 0; i + 2 < fan.size(); ++i) {
    out.push_back(fan[i + 1]);
    out.push_back(fan[i + 2]);
    out.push_back(fan[0]);
  }
  return out;
}

std::vector<glm::vec3> generate_normals(const std::vector<glm::vec3>& positions,
                                        const std::vector<uint32_t>& indices) {
  // Double sums: large meshes add many small faces per vertex.
  std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    uint32_t i0 = indices[t], i1 = indices[t + 1], i2 = indices[t + 2];
    glm::dvec3 p0(positions[i0]), p1(positions[i1]), p2(positions[i2]);
    glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);  // length = 2 * area
    sum[i0] += n;
    sum[i1] += n;
    sum[i2] += n;
  }
  std::vector<glm::vec3> out(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    double len = glm::length(sum[v]);
    out[v] = len > 0.0 && std::isfinite(len) ? glm::vec3(sum[v] / len) : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  return out;
}

bool faces_agree_at_vertices(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices) {
  std::vector<glm::dvec3> first(positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t i0 = indices[t], i1 = indices[t + 1], i2 = indices[t + 2];
    const glm::dvec3 p0(positions[i0]);
    const glm::dvec3 n = glm::cross(glm::dvec3(positions[i1]) - p0, glm::dvec3(positions[i2]) - p0);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    for (uint32_t i : {i0, i1, i2}) {
      if (first[i] == glm::dvec3(0.0)) {
        first[i] = n / len;
      } else if (glm::dot(first[i], n / len) < 1.0 - 1e-6) {
        return false;
      }
    }
  }
  return true;
}

glm::vec3 any_orthogonal(const glm::vec3& n) {
  glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  return glm::normalize(glm::cross(n, axis));
}

std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& normals,
                                         const std::vector<glm::vec2>& texcoords,
                                         const std::vector<uint32_t>& indices) {
  std::vector<glm::dvec3> tan(positions.size(), glm::dvec3(0.0));
  std::vector<glm::dvec3> bitan(positions.size(), glm::dvec3(0.0));
  if (texcoords.size() == positions.size()) {
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      uint32_t i0 = indices[t], i1 = indices[t + 1], i2 = indices[t + 2];
      glm::dvec3 e1 = glm::dvec3(positions[i1]) - glm::dvec3(positions[i0]);
      glm::dvec3 e2 = glm::dvec3(positions[i2]) - glm::dvec3(positions[i0]);
      glm::dvec2 d1 = glm::dvec2(texcoords[i1]) - glm::dvec2(texcoords[i0]);
      glm::dvec2 d2 = glm::dvec2(texcoords[i2]) - glm::dvec2(texcoords[i0]);
      double det = d1.x * d2.y - d2.x * d1.y;
      if (!(std::abs(det) > 1e-20)) continue;  // degenerate UV mapping: no information
      glm::dvec3 t_dir = (e1 * d2.y - e2 * d1.y) / det;
      // dP/dv points where v grows, down the image: glTF's normal maps (and
      // MikkTSpace run on the 1 - v that exporters use) point +Y up the
      // image, along -dP/dv.
      glm::dvec3 b_dir = -(e2 * d1.x - e1 * d2.x) / det;
      for (uint32_t i : {i0, i1, i2}) {
        tan[i] += t_dir;
        bitan[i] += b_dir;
      }
    }
  }
  std::vector<glm::vec4> out(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    glm::dvec3 n(normals[v]);
    glm::dvec3 t = tan[v] - n * glm::dot(n, tan[v]);
    double len = glm::length(t);
    glm::vec3 unit_t = len > 1e-20 && std::isfinite(len) ? glm::vec3(t / len) : any_orthogonal(normals[v]);
    float w = glm::dot(glm::cross(n, glm::dvec3(unit_t)), bitan[v]) < 0.0 ? -1.0f : 1.0f;
    out[v] = glm::vec4(unit_t, w);
  }
  return out;
}

}  // namespace cr

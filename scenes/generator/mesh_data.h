#pragma once
// Vertex streams of one generated primitive, before it becomes glTF accessors.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cr::gen {

struct MeshData {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> tangents;  // empty unless the material has a normal map
  std::vector<glm::vec4> colors;    // COLOR_0, linear RGBA; empty when unused
  std::vector<uint32_t> indices;    // triangle list, counter-clockwise front faces

  size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace cr::gen

#pragma once
// Geometry derived at load time: triangle lists from strips and fans, vertex
// normals where a file has none, and tangent frames for normal mapping.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

// glTF TRIANGLE_STRIP / TRIANGLE_FAN index sequences (>= 3 entries) to
// triangle lists of count - 2 triangles, keeping the winding order of the spec.
std::vector<uint32_t> triangulate_strip(const std::vector<uint32_t>& strip);
std::vector<uint32_t> triangulate_fan(const std::vector<uint32_t>& fan);

// Area-weighted vertex normals (sum of the face normals of the triangles that
// use a vertex, each weighted by its area), normalised. A vertex in no
// triangle of non-zero area gets +Z.
std::vector<glm::vec3> generate_normals(const std::vector<glm::vec3>& positions,
                                        const std::vector<uint32_t>& indices);

// Per-vertex tangents for normal mapping: each triangle's UV-derivative tangent
// and bitangent (Lengyel's method) are summed per vertex, the tangent is
// Gram-Schmidt orthogonalised against the vertex normal, and w holds the
// handedness (+1 or -1) so that bitangent = w * cross(normal, tangent).
// MikkTSpace, the reference glTF tangent space, is not packaged for Debian;
// this gives the same frames for well-parameterised meshes and differs only
// where UV charts are split or degenerate. Vertices without usable UVs get an
// arbitrary unit tangent orthogonal to the normal.
std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& normals,
                                         const std::vector<glm::vec2>& texcoords,
                                         const std::vector<uint32_t>& indices);

// A unit vector orthogonal to unit `n`.
glm::vec3 any_orthogonal(const glm::vec3& n);

}  // namespace cr

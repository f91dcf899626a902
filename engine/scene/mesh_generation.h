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

// Whether every vertex is shared only by triangles of one orientation (unit
// face normals within 1e-6 of each other; zero-area triangles ignored): then
// generate_normals gives each vertex the flat normal of all its triangles,
// and flat shading needs no vertex split.
bool faces_agree_at_vertices(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices);

// Per-vertex tangents for normal mapping, in the tangent space glTF asks
// for (MikkTSpace's conventions): the tangent follows +U, and the bitangent
// cross(normal, tangent) * w points towards the image's top, i.e. where v
// (whose origin is the image's top-left corner in glTF) decreases; w is +1
// or -1. Each triangle's UV-derivative tangent and bitangent (Lengyel's
// method) are summed per vertex, and the tangent is Gram-Schmidt
// orthogonalised against the vertex normal. MikkTSpace itself is not
// packaged for Debian; this gives its frames for well-parameterised meshes
// and differs only where UV charts are split or degenerate. Vertices without
// usable UVs get an arbitrary unit tangent orthogonal to the normal.
std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& normals,
                                         const std::vector<glm::vec2>& texcoords,
                                         const std::vector<uint32_t>& indices);

// A unit vector orthogonal to unit `n`.
glm::vec3 any_orthogonal(const glm::vec3& n);

}  // namespace cr

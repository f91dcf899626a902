// Strip/fan conversion, normal and tangent generation as functions.
#include <cmath>

#include <doctest/doctest.h>

#include "engine/scene/mesh_generation.h"
#include "tests/scene/gltf_test_builder.h"

TEST_CASE("strips and fans convert to count - 2 triangles in the spec's vertex order") {
  std::vector<uint32_t> seq = {10, 11, 12, 13, 14};
  CHECK(cr::triangulate_strip(seq) == std::vector<uint32_t>{10, 11, 12, 11, 13, 12, 12, 13, 14});
  CHECK(cr::triangulate_fan(seq) == std::vector<uint32_t>{11, 12, 10, 12, 13, 10, 13, 14, 10});
  CHECK(cr::triangulate_strip({1, 2}).empty());
  CHECK(cr::triangulate_fan({1, 2, 3}).size() == 3);
}

TEST_CASE("generated normals on a box with shared corners are unit and outward") {
  // 8 shared corners: normals are area-weighted averages, pointing out diagonally.
  std::vector<glm::vec3> pos;
  for (int i = 0; i < 8; ++i) pos.emplace_back(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
  std::vector<float> face_pos;
  std::vector<uint32_t> face_idx;
  cr::test::unit_cube(face_pos, face_idx);
  // Map the 24 face vertices onto the 8 shared corners.
  std::vector<uint32_t> idx;
  for (uint32_t i : face_idx) {
    int corner = (face_pos[3 * i] > 0 ? 1 : 0) | (face_pos[3 * i + 1] > 0 ? 2 : 0) | (face_pos[3 * i + 2] > 0 ? 4 : 0);
    idx.push_back(static_cast<uint32_t>(corner));
  }
  std::vector<glm::vec3> n = cr::generate_normals(pos, idx);
  for (int i = 0; i < 8; ++i) {
    CHECK(std::abs(glm::length(n[i]) - 1.0f) < 1e-6f);
    // Outward: within the octant of the corner's diagonal (a corner may belong to
    // one or two triangles of each face, so it is not exactly the diagonal).
    CHECK(glm::dot(n[i], glm::normalize(pos[i])) > 0.5f);
    CHECK(glm::all(glm::greaterThan(n[i] * pos[i], glm::vec3(0.0f))));
  }
}

TEST_CASE("generated tangents are unit, orthogonal to the normal, with handedness in w") {
  // A curved patch: normals are not the face normals, so orthogonalisation matters.
  std::vector<glm::vec3> pos = {{0, 0, 0}, {1, 0, 0.2f}, {1, 1, 0.4f}, {0, 1, 0.1f}};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  std::vector<glm::vec3> n = cr::generate_normals(pos, idx);
  // glTF's v grows down the image and a normal map's +Y points up it: with v
  // growing along +Y the bitangent cross(N, T) * w (+Y for w = 1) must point
  // along -Y, so w = -1; with v growing along -Y, w = +1.
  for (float flip : {1.0f, -1.0f}) {
    std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {1, flip}, {0, flip}};
    std::vector<glm::vec4> t = cr::generate_tangents(pos, n, uv, idx);
    for (size_t v = 0; v < pos.size(); ++v) {
      CHECK(std::abs(glm::length(glm::vec3(t[v])) - 1.0f) < 1e-5f);
      CHECK(std::abs(glm::dot(glm::vec3(t[v]), n[v])) < 1e-5f);
      CHECK(t[v].w == -flip);
      CHECK(t[v].x > 0.9f);  // U runs along +X
    }
  }
  // Without UVs there is still a valid frame.
  std::vector<glm::vec4> t = cr::generate_tangents(pos, n, {}, idx);
  for (size_t v = 0; v < pos.size(); ++v) CHECK(std::abs(glm::dot(glm::vec3(t[v]), n[v])) < 1e-5f);
}

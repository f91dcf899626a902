#include "scenes/generator/shapes.h"

#include <array>
#include <cmath>
#include <numbers>

namespace cr::gen {

void add_polygon(MeshData& mesh, const std::vector<glm::vec3>& ccw, const TextureFrame& frame, bool with_tangents) {
  // Newell's method: robust normal of a planar polygon from its winding.
  glm::vec3 normal(0.0f);
  for (size_t i = 0; i < ccw.size(); ++i) {
    const glm::vec3& a = ccw[i];
    const glm::vec3& b = ccw[(i + 1) % ccw.size()];
    normal += glm::vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  normal = glm::normalize(normal);
  // Bitangent = cross(normal, tangent) * w must point up the image, i.e. against `down`.
  const float handedness = glm::dot(glm::cross(normal, frame.right), frame.down) < 0.0f ? 1.0f : -1.0f;
  const auto first = static_cast<uint32_t>(mesh.positions.size());
  for (const glm::vec3& p : ccw) {
    const glm::vec3 d = p - frame.origin;
    mesh.positions.push_back(p);
    mesh.normals.push_back(normal);
    mesh.uvs.push_back((frame.offset + glm::vec2(glm::dot(d, frame.right), glm::dot(d, frame.down))) / frame.tile);
    if (with_tangents) mesh.tangents.emplace_back(frame.right, handedness);
  }
  for (uint32_t i = 1; i + 1 < ccw.size(); ++i) mesh.indices.insert(mesh.indices.end(), {first, first + i, first + i + 1});
}

namespace {

constexpr glm::vec2 kFacadeTile{4.0f, 3.2f};
constexpr glm::vec3 kUp{0.0f, 1.0f, 0.0f};

// A face given by its top-left corner and edges to the right and downwards
// (as seen from the front), mapped with texture axes along those edges.
void add_rect(MeshData& mesh, const glm::vec3& top_left, const glm::vec3& right, const glm::vec3& down,
              const glm::vec2& tile, const glm::vec2& offset, bool with_tangents) {
  const TextureFrame frame{top_left, glm::normalize(right), glm::normalize(down), tile, offset};
  add_polygon(mesh, {top_left, top_left + down, top_left + down + right, top_left + right}, frame, with_tangents);
}

// An oriented box: centre, three orthonormal axes and half extents along them.
void add_oriented_box(MeshData& mesh, const glm::vec3& centre, const std::array<glm::vec3, 3>& axes,
                      const glm::vec3& half, float tile, bool with_tangents) {
  const glm::vec2 t(tile);
  for (int a = 0; a < 3; ++a) {
    for (const float sign : {1.0f, -1.0f}) {
      // Face normal along +-axes[a]; its right and down edges along the other two axes.
      const glm::vec3 n = axes[size_t(a)] * sign;
      const int r = (a + 1) % 3, d = (a + 2) % 3;
      glm::vec3 right = axes[size_t(r)] * (2.0f * half[r]);
      const glm::vec3 down = axes[size_t(d)] * (-2.0f * half[d]);
      if (glm::dot(glm::cross(right, -down), n) < 0.0f) right = -right;
      const glm::vec3 top_left = centre + n * half[a] - right * 0.5f - down * 0.5f;
      add_rect(mesh, top_left, right, down, t, glm::vec2(0.0f), with_tangents);
    }
  }
}

}  // namespace

MeshData building_walls(float width, float depth, float wall_height, float foundation, float gable_rise) {
  MeshData mesh;
  const float hx = 0.5f * width, hz = 0.5f * depth;
  const glm::vec3 down(0.0f, -(wall_height + foundation), 0.0f);
  // Walls counter-clockwise seen from above: +z, +x, -z, -x; u runs on around the corners.
  const std::array<glm::vec3, 4> top_left{glm::vec3(-hx, wall_height, hz), glm::vec3(hx, wall_height, hz),
                                          glm::vec3(hx, wall_height, -hz), glm::vec3(-hx, wall_height, -hz)};
  const std::array<glm::vec3, 4> right{glm::vec3(width, 0, 0), glm::vec3(0, 0, -depth), glm::vec3(-width, 0, 0),
                                       glm::vec3(0, 0, depth)};
  float u = 0.0f;
  for (size_t k = 0; k < 4; ++k) {
    add_rect(mesh, top_left[k], right[k], down, kFacadeTile, glm::vec2(u, 0.0f), true);
    if (gable_rise > 0.0f && (k == 1 || k == 3)) {
      const glm::vec3 apex = top_left[k] + 0.5f * right[k] + kUp * gable_rise;
      const TextureFrame frame{top_left[k], glm::normalize(right[k]), -kUp, kFacadeTile, glm::vec2(u, 0.0f)};
      add_polygon(mesh, {top_left[k], top_left[k] + right[k], apex}, frame, true);
    }
    u += glm::length(right[k]);
  }
  return mesh;
}

MeshData gable_roof(float width, float depth, float wall_height, float rise, float overhang, float thickness) {
  MeshData mesh;
  const float run = 0.5f * depth;
  const float slope = rise / run;
  for (const float side : {1.0f, -1.0f}) {
    // Top surface runs from the ridge (z = 0) out past the eave by the overhang.
    const glm::vec3 ridge(0.0f, wall_height + rise, 0.0f);
    const glm::vec3 eave(0.0f, wall_height - overhang * slope, side * (run + overhang));
    const glm::vec3 along = glm::normalize(eave - ridge);
    const glm::vec3 normal = glm::normalize(glm::vec3(0.0f, 1.0f, side * slope));
    const float length = glm::length(eave - ridge);
    const glm::vec3 centre = 0.5f * (ridge + eave) - normal * (0.5f * thickness);
    add_oriented_box(mesh, centre, {glm::vec3(1, 0, 0), along, normal},
                     glm::vec3(0.5f * width + overhang, 0.5f * length, 0.5f * thickness), 1.0f, false);
  }
  return mesh;
}

MeshData box(const glm::vec3& size, float tile, bool with_tangents) {
  MeshData mesh;
  add_oriented_box(mesh, glm::vec3(0.0f), {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)}, 0.5f * size,
                   tile, with_tangents);
  return mesh;
}

MeshData uv_sphere(float radius, int segments, int rings) {
  MeshData mesh;
  for (int r = 0; r <= rings; ++r) {
    const double theta = std::numbers::pi * r / rings;  // from the north pole
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      const glm::vec3 n(static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta)),
                        static_cast<float>(std::sin(theta) * std::cos(phi)));
      mesh.positions.push_back(n * radius);
      mesh.normals.push_back(n);
      mesh.uvs.emplace_back(float(s) / segments, float(r) / rings);
    }
  }
  const auto row = static_cast<uint32_t>(segments + 1);
  for (uint32_t r = 0; r < uint32_t(rings); ++r) {
    for (uint32_t s = 0; s < uint32_t(segments); ++s) {
      const uint32_t a = r * row + s, b = a + 1, c = a + row, d = c + 1;
      if (r != 0) mesh.indices.insert(mesh.indices.end(), {a, c, b});
      if (r + 1 != uint32_t(rings)) mesh.indices.insert(mesh.indices.end(), {b, c, d});
    }
  }
  return mesh;
}

MeshData upright_quad(float width, float height, const glm::vec2& tile) {
  MeshData mesh;
  add_rect(mesh, glm::vec3(-0.5f * width, height, 0.0f), glm::vec3(width, 0, 0), glm::vec3(0, -height, 0), tile,
           glm::vec2(0.0f), false);
  return mesh;
}

MeshData crossed_cards(float width, float height) {
  MeshData mesh;
  const glm::vec2 tile(width, height);
  add_rect(mesh, glm::vec3(-0.5f * width, height, 0.0f), glm::vec3(width, 0, 0), glm::vec3(0, -height, 0), tile,
           glm::vec2(0.0f), false);
  add_rect(mesh, glm::vec3(0.0f, height, 0.5f * width), glm::vec3(0, 0, -width), glm::vec3(0, -height, 0), tile,
           glm::vec2(0.0f), false);
  return mesh;
}

}  // namespace cr::gen

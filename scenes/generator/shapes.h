#pragma once
// Mesh builders for the default scene's props and buildings. Every face gets
// a planar texture mapping in metres (u to the right, v down the face as seen
// from the front), so tiling materials keep their scale on any object.
#include <vector>

#include "scenes/generator/mesh_data.h"

namespace cr::gen {

// Planar texture mapping of a face: uv = (offset + (dot(p - origin, right),
// dot(p - origin, down))) / tile, with right and down unit vectors in the face.
struct TextureFrame {
  glm::vec3 origin{0.0f};
  glm::vec3 right{1.0f, 0.0f, 0.0f};
  glm::vec3 down{0.0f, -1.0f, 0.0f};
  glm::vec2 tile{1.0f};
  glm::vec2 offset{0.0f};
};

// A convex planar polygon, vertices counter-clockwise seen from the front.
// with_tangents adds TANGENT (u direction, w = handedness of v).
void add_polygon(MeshData& mesh, const std::vector<glm::vec3>& ccw, const TextureFrame& frame, bool with_tangents);

// Walls of a building centred on the origin: width along x, depth along z,
// from y = -foundation (buried, for sloping ground) to wall_height, with
// triangular gables on the +-x walls when gable_rise > 0. Textured with the
// 4 m x 3.2 m facade bay, windows continuing around the corners; has tangents.
MeshData building_walls(float width, float depth, float wall_height, float foundation, float gable_rise);

// A pitched roof with its ridge along x over building_walls of the same size:
// two slabs of the given thickness overhanging the walls on all sides.
MeshData gable_roof(float width, float depth, float wall_height, float rise, float overhang, float thickness);

// An axis-aligned box centred on the origin, textured per metre / tile.
MeshData box(const glm::vec3& size, float tile, bool with_tangents);

// A sphere centred on the origin (UVs: longitude, latitude).
MeshData uv_sphere(float radius, int segments, int rings);

// A vertical rectangle in the xy-plane facing +z, bottom edge centred on the
// origin. tile = size of one texture repeat in metres.
MeshData upright_quad(float width, float height, const glm::vec2& tile);

// Two upright quads crossing at right angles, for a tree on a cut-out card;
// the texture covers each quad exactly once.
MeshData crossed_cards(float width, float height);

}  // namespace cr::gen

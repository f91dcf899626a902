#pragma once
// The generated terrain: a height field over a 131 km square centred on the
// world origin, meshed as a restricted quadtree of 8x8-cell patches whose
// cells are fine near the village (2-8 m within 200 m), 256-512 m on the
// mountain range and up to 2 km on the far plains. Patch edges facing a finer neighbour gain the neighbour's edge
// midpoints, so the mesh is watertight without skirts.
#include <vector>

#include "scenes/generator/mesh_data.h"

namespace cr::gen {

// Ground height (metres, +Y) at world (x, z). Deterministic and smooth.
double terrain_height(double x, double z);

struct TerrainChunk {
  MeshData mesh;
  // Far chunks carry per-vertex albedo (grass, rock, snow) in COLOR_0 and no
  // texture: past a few km the tiling texture is minified to its mean anyway.
  bool far = false;
};

// Meshes the terrain. detail >= 1 scales the allowed screen-space height
// error (and so the triangle count); patches are grouped into chunks so the
// renderer can cull them. near_albedo is the linear mean colour of the near
// ground texture, used for far lowlands so the material switch is invisible.
std::vector<TerrainChunk> build_terrain(int detail, const glm::vec3& near_albedo);

}  // namespace cr::gen

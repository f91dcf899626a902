#pragma once
// Loads a written .glb back with tinygltf and checks what the generator
// promises: it parses cleanly, images decode, POSITION accessors carry
// min/max, and the camera and KHR_lights_punctual sun are present.
#include <cstddef>
#include <string>

namespace cr::gen {

struct GlbSummary {
  size_t nodes = 0;
  size_t meshes = 0;
  size_t materials = 0;
  size_t images = 0;
  size_t triangles_drawn = 0;  // summed over the nodes that place meshes
};

// Throws cr::InputError naming the file and the first problem found.
GlbSummary check_glb(const std::string& path);

}  // namespace cr::gen

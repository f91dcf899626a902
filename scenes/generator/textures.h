#pragma once
// Procedural RGBA8 textures of the default scene. Colour images are authored
// in sRGB; data images (metallic-roughness, normals) are linear. All tile
// seamlessly (noise lattices wrap with the image) unless noted.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace cr::gen {

struct ImageRGBA8 {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // row-major, top row first
};

// Grass with rock and dirt patches; one repeat covers 8 m x 8 m of ground.
ImageRGBA8 ground_base_color();
// G = roughness (grass rougher than rock), B = metallic (0).
ImageRGBA8 ground_metallic_roughness();

// One facade bay, 4 m wide and 3.2 m tall: plaster wall with a framed window
// and a stone sill. The normal map (tangent space, +Y = image up) recesses the
// window and roughens the plaster; the metallic-roughness map makes glass glossy.
ImageRGBA8 facade_base_color();
ImageRGBA8 facade_normal();
ImageRGBA8 facade_metallic_roughness();

// Picket fence, 1.5 m x 1.5 m per repeat; alpha 0 between the pickets (MASK).
ImageRGBA8 fence_base_color();
// A whole tree on one card (trunk and leafy crown, alpha 0 outside); clamps.
ImageRGBA8 foliage_base_color();
// Lettering of the emissive sign ("CPURENDER" in a frame) on black; clamps.
ImageRGBA8 sign_emissive();

// Mean colour of an sRGB image in linear units (alpha ignored).
glm::vec3 mean_linear_color(const ImageRGBA8& image);

}  // namespace cr::gen

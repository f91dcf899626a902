#include "scenes/generator/glb_check.h"

#include <algorithm>

#include <tiny_gltf.h>

#include "engine/core/error.h"

namespace cr::gen {

namespace {

size_t triangles_below(const tinygltf::Model& model, int node) {
  const tinygltf::Node& n = model.nodes[size_t(node)];
  size_t count = 0;
  if (n.mesh >= 0) {
    for (const tinygltf::Primitive& p : model.meshes[size_t(n.mesh)].primitives)
      count += model.accessors[size_t(p.indices)].count / 3;
  }
  for (const int child : n.children) count += triangles_below(model, child);
  return count;
}

}  // namespace

GlbSummary check_glb(const std::string& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  if (!loader.LoadBinaryFromFile(&model, &error, &warning, path)) throw InputError(path, "tinygltf: " + error);
  if (!warning.empty()) throw InputError(path, "tinygltf warning: " + warning);

  for (const tinygltf::Image& image : model.images) {
    if (image.width <= 0 || image.component != 4 || image.image.empty())
      throw InputError(path, "images['" + image.name + "'] did not decode as RGBA8");
  }
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    for (const tinygltf::Primitive& p : model.meshes[m].primitives) {
      for (const char* attribute : {"POSITION", "NORMAL", "TEXCOORD_0"}) {
        if (!p.attributes.count(attribute))
          throw InputError(path, "meshes[" + std::to_string(m) + "] has no " + attribute);
      }
      const tinygltf::Accessor& position = model.accessors[size_t(p.attributes.at("POSITION"))];
      if (position.minValues.size() != 3 || position.maxValues.size() != 3)
        throw InputError(path, "meshes[" + std::to_string(m) + "] POSITION lacks min/max");
      if (p.indices < 0) throw InputError(path, "meshes[" + std::to_string(m) + "] has no indices");
      const int material = p.material;
      if (material >= 0 && model.materials[size_t(material)].normalTexture.index >= 0 && !p.attributes.count("TANGENT"))
        throw InputError(path, "meshes[" + std::to_string(m) + "] has a normal map but no TANGENT");
    }
  }
  if (model.cameras.empty() || model.cameras[0].type != "perspective")
    throw InputError(path, "cameras[0] is not a perspective camera");
  const bool sun_placed = std::any_of(model.nodes.begin(), model.nodes.end(), [](const tinygltf::Node& n) {
    return n.extensions.count("KHR_lights_punctual") != 0;
  });
  if (model.lights.size() != 1 || model.lights[0].type != "directional" || !sun_placed)
    throw InputError(path, "KHR_lights_punctual: expected one directional light placed by a node");
  if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), "KHR_lights_punctual") ==
      model.extensionsUsed.end())
    throw InputError(path, "extensionsUsed lacks KHR_lights_punctual");

  GlbSummary summary{model.nodes.size(), model.meshes.size(), model.materials.size(), model.images.size(), 0};
  for (const int root : model.scenes[size_t(std::max(model.defaultScene, 0))].nodes)
    summary.triangles_drawn += triangles_below(model, root);
  return summary;
}

}  // namespace cr::gen

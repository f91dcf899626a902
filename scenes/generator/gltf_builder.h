#pragma once
// Assembles a tinygltf::Model from generated meshes and images: one binary
// buffer holding every accessor's data and the PNG-encoded images, written
// as a single .glb.
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "scenes/generator/mesh_data.h"
#include "scenes/generator/textures.h"

namespace cr::gen {

class GltfBuilder {
 public:
  GltfBuilder();

  // Encodes the image as PNG into the buffer; returns the image index.
  int add_image(const ImageRGBA8& image);
  // A sampler with trilinear filtering; repeat or clamp-to-edge wrapping.
  int add_sampler(bool repeat);
  int add_texture(int image, int sampler);
  int add_material(const tinygltf::Material& material);
  // Appends the streams as accessors (POSITION with min/max, u16 indices when
  // they fit) and returns a triangle-list primitive without a material, so
  // several meshes can share one set of accessors with different materials.
  tinygltf::Primitive add_primitive(const MeshData& mesh);
  int add_mesh(const std::string& name, std::vector<tinygltf::Primitive> primitives);
  int add_camera(const tinygltf::Camera& camera);
  int add_light(const tinygltf::Light& light);
  int add_node(const tinygltf::Node& node);
  void add_child(int parent, int child);
  void add_root_node(int node);

  tinygltf::Model& model() { return model_; }

 private:
  int add_buffer_view(const void* data, size_t bytes, int target);
  template <typename T>
  int add_accessor(const std::vector<T>& values, int component_type, int type, int target);

  tinygltf::Model model_;
};

// Writes the model as a .glb atomically (a temporary file renamed into place);
// throws cr::InputError naming the path when it cannot be written.
void write_glb(const tinygltf::Model& model, const std::string& path);

}  // namespace cr::gen

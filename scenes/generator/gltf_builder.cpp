#include "scenes/generator/gltf_builder.h"

#include <filesystem>
#include <limits>
#include <system_error>

#include "engine/core/error.h"

// stb_image_write's PNG encoder, private to this file: libtinygltf has its
// own copy, and a static one cannot clash with it.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace cr::gen {

namespace {

void append_bytes(std::vector<unsigned char>* out, const void* data, int size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

std::vector<unsigned char> encode_png(const ImageRGBA8& image) {
  std::vector<unsigned char> png;
  const int ok = stbi_write_png_to_func(
      [](void* context, void* data, int size) { append_bytes(static_cast<std::vector<unsigned char>*>(context), data, size); },
      &png, image.width, image.height, 4, image.rgba.data(), image.width * 4);
  if (!ok) throw Error("scene_generator: PNG encoding of image '" + image.name + "' failed");
  return png;
}

}  // namespace

GltfBuilder::GltfBuilder() {
  model_.asset.version = "2.0";
  model_.asset.generator = "cpurender scene_generator";
  model_.buffers.emplace_back();
  model_.scenes.emplace_back();
  model_.scenes[0].name = "default";
  model_.defaultScene = 0;
}

int GltfBuilder::add_buffer_view(const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model_.buffers[0].data;
  buffer.resize((buffer.size() + 3) & ~size_t(3), 0);  // 4-byte alignment for every accessor type
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* begin = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), begin, begin + bytes);
  model_.bufferViews.push_back(view);
  return static_cast<int>(model_.bufferViews.size() - 1);
}

template <typename T>
int GltfBuilder::add_accessor(const std::vector<T>& values, int component_type, int type, int target) {
  tinygltf::Accessor accessor;
  accessor.bufferView = add_buffer_view(values.data(), values.size() * sizeof(T), target);
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = values.size();
  model_.accessors.push_back(accessor);
  return static_cast<int>(model_.accessors.size() - 1);
}

int GltfBuilder::add_image(const ImageRGBA8& image) {
  const std::vector<unsigned char> png = encode_png(image);
  tinygltf::Image out;
  out.name = image.name;
  out.mimeType = "image/png";
  out.bufferView = add_buffer_view(png.data(), png.size(), 0);
  model_.images.push_back(out);
  return static_cast<int>(model_.images.size() - 1);
}

int GltfBuilder::add_sampler(bool repeat) {
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = repeat ? TINYGLTF_TEXTURE_WRAP_REPEAT : TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model_.samplers.push_back(sampler);
  return static_cast<int>(model_.samplers.size() - 1);
}

int GltfBuilder::add_texture(int image, int sampler) {
  tinygltf::Texture texture;
  texture.source = image;
  texture.sampler = sampler;
  model_.textures.push_back(texture);
  return static_cast<int>(model_.textures.size() - 1);
}

int GltfBuilder::add_material(const tinygltf::Material& material) {
  model_.materials.push_back(material);
  return static_cast<int>(model_.materials.size() - 1);
}

tinygltf::Primitive GltfBuilder::add_primitive(const MeshData& mesh) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const int position = add_accessor(mesh.positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                    TINYGLTF_TARGET_ARRAY_BUFFER);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  model_.accessors[size_t(position)].minValues = {lo.x, lo.y, lo.z};
  model_.accessors[size_t(position)].maxValues = {hi.x, hi.y, hi.z};
  primitive.attributes["POSITION"] = position;
  primitive.attributes["NORMAL"] =
      add_accessor(mesh.normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.attributes["TEXCOORD_0"] =
      add_accessor(mesh.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!mesh.tangents.empty()) {
    primitive.attributes["TANGENT"] =
        add_accessor(mesh.tangents, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  if (!mesh.colors.empty()) {
    primitive.attributes["COLOR_0"] =
        add_accessor(mesh.colors, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  if (mesh.positions.size() <= std::numeric_limits<uint16_t>::max()) {
    const std::vector<uint16_t> indices(mesh.indices.begin(), mesh.indices.end());
    primitive.indices = add_accessor(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                     TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  } else {
    primitive.indices = add_accessor(mesh.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                     TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  }
  return primitive;
}

int GltfBuilder::add_mesh(const std::string& name, std::vector<tinygltf::Primitive> primitives) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives = std::move(primitives);
  model_.meshes.push_back(std::move(mesh));
  return static_cast<int>(model_.meshes.size() - 1);
}

int GltfBuilder::add_camera(const tinygltf::Camera& camera) {
  model_.cameras.push_back(camera);
  return static_cast<int>(model_.cameras.size() - 1);
}

int GltfBuilder::add_light(const tinygltf::Light& light) {
  model_.lights.push_back(light);
  return static_cast<int>(model_.lights.size() - 1);
}

int GltfBuilder::add_node(const tinygltf::Node& node) {
  model_.nodes.push_back(node);
  return static_cast<int>(model_.nodes.size() - 1);
}

void GltfBuilder::add_child(int parent, int child) { model_.nodes[size_t(parent)].children.push_back(child); }

void GltfBuilder::add_root_node(int node) { model_.scenes[0].nodes.push_back(node); }

void write_glb(const tinygltf::Model& model, const std::string& path) {
  const std::string temp = path + ".tmp";
  tinygltf::TinyGLTF writer;
  const bool written = writer.WriteGltfSceneToFile(&model, temp, /*embedImages=*/true, /*embedBuffers=*/true,
                                                   /*prettyPrint=*/false, /*writeBinary=*/true);
  std::error_code ec;
  if (written) std::filesystem::rename(temp, path, ec);
  if (!written || ec) {
    std::filesystem::remove(temp, ec);
    throw InputError(path, "cannot write the .glb (is the directory writable?)");
  }
}

}  // namespace cr::gen

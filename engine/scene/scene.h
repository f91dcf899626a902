#pragma once
// The in-memory scene: what the glTF loader produces and the renderer consumes.
// Everything here has been validated; renderer code may index without checks.
//
// Conventions: glTF world space (metres, +Y up, right-handed). Geometry is
// flattened: every (node, mesh primitive) pair becomes one Draw with its world
// matrix. Triangles only (strips/fans converted at load); indices are 32-bit.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace cr {

enum class Wrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class Filter : uint8_t { Nearest, Linear };

struct Sampler {
  Wrap wrap_s = Wrap::Repeat;
  Wrap wrap_t = Wrap::Repeat;
  Filter mag = Filter::Linear;
  Filter min = Filter::Linear;         // filter within a mip level
  std::optional<Filter> mip;           // nullopt: no mipmapping (base level only)
};

// One mip level of an RGBA8 image: texels as stored in the file (8-bit sRGB
// or linear channels, alpha linear), decoded when sampled (engine/shading/texel_decode.h).
struct MipLevel {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width*height*4
};

// A decoded image with its full mip chain (generated at load, box filter in
// linear space for sRGB images). Colour space is decided by the material slot
// that uses it: base colour and emissive are sRGB, the others linear.
struct Image {
  std::string name;
  bool srgb = false;
  // mips[0] is the largest level kept (the file's size unless the texture
  // budget dropped top levels: GltfLoadOptions::texture_decode_budget), each
  // next level half the last (rounded down, at least 1), down to 1x1.
  std::vector<MipLevel> mips;
};

// KHR_texture_transform of one texture reference: uv' = T * R * S * uv with
// the extension's offset, rotation (radians, counter-clockwise in UV space as
// the extension defines it) and scale.
struct UvTransform {
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;
  glm::vec2 scale{1.0f};
  bool identity() const { return offset == glm::vec2(0.0f) && rotation == 0.0f && scale == glm::vec2(1.0f); }
};

struct TextureRef {
  int image = -1;     // index into Scene::images, -1 = none
  int sampler = -1;   // index into Scene::samplers, -1 = default sampler
  int texcoord = 0;   // 0: TEXCOORD_0, 1: TEXCOORD_1 (after KHR_texture_transform's texCoord override)
  float scale = 1.0f; // normalTexture.scale or occlusionTexture.strength
  UvTransform transform{};  // KHR_texture_transform (identity without it)
  bool valid() const { return image >= 0; }
};

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

struct Material {
  std::string name;
  glm::vec4 base_color_factor{1.0f};
  TextureRef base_color;
  float metallic_factor = 1.0f;
  float roughness_factor = 1.0f;
  TextureRef metallic_roughness;  // G = roughness, B = metallic
  TextureRef normal;              // scale in TextureRef::scale
  TextureRef occlusion;           // strength in TextureRef::scale
  glm::vec3 emissive_factor{0.0f};
  float emissive_strength = 1.0f;  // KHR_materials_emissive_strength (multiplies emissive_factor)
  TextureRef emissive;
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  bool unlit = false;  // KHR_materials_unlit: radiance = base colour (times the emissive convention), no lighting
};

// Vertex streams of one primitive, all of equal length. Optional streams are
// empty when absent (normals are always generated; tangents are generated when
// the material has a normal map and the file has none).
struct Primitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec4> tangents;   // xyz tangent, w = bitangent sign
  std::vector<glm::vec2> texcoords;  // TEXCOORD_0
  std::vector<glm::vec2> texcoords1; // TEXCOORD_1 (loaded when a material texture uses it)
  std::vector<glm::vec4> colors;     // COLOR_0 (linear RGBA)
  std::vector<uint32_t> indices;     // triangle list, 3 per triangle
  int material = -1;                 // -1 = default material
  glm::vec3 bounds_min{0.0f};        // object-space AABB
  glm::vec3 bounds_max{0.0f};
  size_t triangle_count() const { return indices.size() / 3; }
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
};

// One primitive placed in the world.
struct Draw {
  int mesh = 0;
  int primitive = 0;
  glm::mat4 world{1.0f};
  glm::mat3 normal_matrix{1.0f};  // inverse-transpose of world's upper 3x3
  bool mirrored = false;          // det(world) < 0 flips the winding
  glm::vec3 world_bounds_min{0.0f};
  glm::vec3 world_bounds_max{0.0f};
};

// A camera from the glTF file (placed by its node).
struct GltfCamera {
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov_rad = 0.8f;
  float znear = 0.1f;
  std::optional<float> aspect;
  // Orthographic cameras: half the view's height and width in metres (ymag,
  // xmag) and the far plane; yfov_rad is unused for them.
  bool orthographic = false;
  float ymag = 1.0f;
  float xmag = 1.0f;
  float zfar = 100.0f;
};

// KHR_lights_punctual directional light, used as the sun.
struct GltfSun {
  glm::vec3 direction_to_sun{0.0f, 1.0f, 0.0f};  // unit, world space
  glm::vec3 color{1.0f};
  float intensity = 1.0f;  // lux
};

// KHR_lights_punctual point or spot light, placed by its node. Intensity is
// luminous intensity in candela (lm/sr); illuminance at distance d is
// intensity / d^2 times the range window and, for spots, the cone falloff.
struct PunctualLight {
  enum class Type : uint8_t { Point, Spot };
  Type type = Type::Point;
  std::string name;
  glm::vec3 position{0.0f};                  // world space
  glm::vec3 direction{0.0f, 0.0f, -1.0f};    // unit, world space: where a spot shines (its node's -Z)
  glm::vec3 color{1.0f};                     // linear RGB
  float intensity = 1.0f;                    // candela
  float range = 0.0f;                        // 0: unlimited; else the distance where the light reaches zero
  float inner_cone_rad = 0.0f;               // spots: full intensity inside this angle from direction
  float outer_cone_rad = 0.7853982f;         // spots: zero outside this angle
};

// Skins, animations and morph targets kept from the file to pose the scene at
// a time (scene_animation.h); draws and primitives hold the pose.
struct SceneAnimation;

struct Scene {
  std::string source;  // path of the glTF file
  std::vector<Image> images;
  std::vector<Sampler> samplers;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Draw> draws;
  std::vector<GltfCamera> cameras;
  std::optional<GltfSun> sun;
  std::vector<PunctualLight> lights;  // point and spot lights (KHR_lights_punctual)
  std::shared_ptr<const SceneAnimation> animation;  // null when the file has nothing to animate
  glm::vec3 bounds_min{0.0f};  // world AABB of all draws
  glm::vec3 bounds_max{0.0f};
  // What the automatic view frames: the world AABB of the pose the scene was
  // loaded or described at. Playback (pose_scene per frame) leaves it, so an
  // automatic view holds still while the scene moves.
  glm::vec3 framing_min{0.0f};
  glm::vec3 framing_max{0.0f};

  const Primitive& primitive(const Draw& d) const { return meshes[d.mesh].primitives[d.primitive]; }
  size_t triangle_count() const {
    size_t n = 0;
    for (const Draw& d : draws) n += primitive(d).triangle_count();
    return n;
  }
};

}  // namespace cr

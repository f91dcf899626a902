#include "scenes/generator/default_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/gtc/quaternion.hpp>

#include "scenes/generator/gltf_builder.h"
#include "scenes/generator/shapes.h"
#include "scenes/generator/terrain.h"
#include "scenes/generator/textures.h"

namespace cr::gen {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

struct Materials {
  int ground, terrain_far, facade, roof_tiles, concrete, polished_metal, rough_clay, sign_face, steel, thin_wall,
      fence, foliage, glass;
};

tinygltf::Material pbr(const std::string& name, const glm::dvec4& base_color, double metallic, double roughness) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {base_color.r, base_color.g, base_color.b, base_color.a};
  m.pbrMetallicRoughness.metallicFactor = metallic;
  m.pbrMetallicRoughness.roughnessFactor = roughness;
  m.emissiveFactor = {0.0, 0.0, 0.0};
  return m;
}

Materials add_materials(GltfBuilder& gltf, const ImageRGBA8& ground_color) {
  const int repeat = gltf.add_sampler(true), clamp = gltf.add_sampler(false);
  const int ground_bc = gltf.add_texture(gltf.add_image(ground_color), repeat);
  const int ground_mr = gltf.add_texture(gltf.add_image(ground_metallic_roughness()), repeat);
  const int facade_bc = gltf.add_texture(gltf.add_image(facade_base_color()), repeat);
  const int facade_n = gltf.add_texture(gltf.add_image(facade_normal()), repeat);
  const int facade_mr = gltf.add_texture(gltf.add_image(facade_metallic_roughness()), repeat);
  const int fence_bc = gltf.add_texture(gltf.add_image(fence_base_color()), repeat);
  const int foliage_bc = gltf.add_texture(gltf.add_image(foliage_base_color()), clamp);
  const int sign_e = gltf.add_texture(gltf.add_image(sign_emissive()), clamp);

  Materials m{};
  tinygltf::Material ground = pbr("ground_grass_rock", glm::dvec4(1.0), 1.0, 1.0);
  ground.pbrMetallicRoughness.baseColorTexture.index = ground_bc;
  ground.pbrMetallicRoughness.metallicRoughnessTexture.index = ground_mr;
  m.ground = gltf.add_material(ground);
  // Albedo comes from COLOR_0 (grass, forest, rock, snow).
  m.terrain_far = gltf.add_material(pbr("terrain_far_vertex_color", glm::dvec4(1.0), 0.0, 0.9));

  tinygltf::Material facade = pbr("facade_plaster_windows", glm::dvec4(1.0), 1.0, 1.0);
  facade.pbrMetallicRoughness.baseColorTexture.index = facade_bc;
  facade.pbrMetallicRoughness.metallicRoughnessTexture.index = facade_mr;
  facade.normalTexture.index = facade_n;
  facade.normalTexture.scale = 1.0;
  m.facade = gltf.add_material(facade);

  m.roof_tiles = gltf.add_material(pbr("roof_tiles", {0.30, 0.09, 0.06, 1.0}, 0.0, 0.75));
  m.concrete = gltf.add_material(pbr("concrete", {0.42, 0.42, 0.40, 1.0}, 0.0, 0.9));
  m.polished_metal = gltf.add_material(pbr("polished_metal", {0.95, 0.93, 0.88, 1.0}, 1.0, 0.15));
  m.rough_clay = gltf.add_material(pbr("rough_red_clay", {0.60, 0.13, 0.09, 1.0}, 0.0, 0.85));
  m.steel = gltf.add_material(pbr("brushed_steel", {0.55, 0.56, 0.58, 1.0}, 1.0, 0.45));

  tinygltf::Material sign = pbr("sign_emissive_lettering", {0.02, 0.02, 0.02, 1.0}, 0.0, 0.4);
  sign.emissiveTexture.index = sign_e;
  sign.emissiveFactor = {1.0, 1.0, 1.0};
  m.sign_face = gltf.add_material(sign);

  tinygltf::Material thin_wall = pbr("thin_wall_double_sided", {0.55, 0.62, 0.70, 1.0}, 0.0, 0.8);
  thin_wall.doubleSided = true;
  m.thin_wall = gltf.add_material(thin_wall);

  tinygltf::Material fence = pbr("fence_cutout", glm::dvec4(1.0), 0.0, 0.8);
  fence.pbrMetallicRoughness.baseColorTexture.index = fence_bc;
  fence.alphaMode = "MASK";
  fence.alphaCutoff = 0.5;
  fence.doubleSided = true;
  m.fence = gltf.add_material(fence);

  tinygltf::Material foliage = pbr("foliage_card", glm::dvec4(1.0), 0.0, 0.9);
  foliage.pbrMetallicRoughness.baseColorTexture.index = foliage_bc;
  foliage.alphaMode = "MASK";
  foliage.alphaCutoff = 0.5;
  foliage.doubleSided = true;
  m.foliage = gltf.add_material(foliage);

  tinygltf::Material glass = pbr("glass_pane", {0.80, 0.90, 0.95, 0.25}, 0.0, 0.05);
  glass.alphaMode = "BLEND";
  glass.doubleSided = true;
  m.glass = gltf.add_material(glass);
  return m;
}

std::vector<double> yaw_rotation(double yaw_deg) {
  const double half = 0.5 * yaw_deg * kDegToRad;
  return {0.0, std::sin(half), 0.0, std::cos(half)};
}

// Lowest ground under a rotated rectangular footprint, so walls reach the
// ground on every side (their buried foundation covers the rest).
double footprint_ground(double x, double z, double half_w, double half_d, double yaw_deg) {
  const double c = std::cos(yaw_deg * kDegToRad), s = std::sin(yaw_deg * kDegToRad);
  double lowest = terrain_height(x, z);
  for (const double u : {-half_w, half_w}) {
    for (const double v : {-half_d, half_d}) {
      // glTF yaw about +Y maps local (u, v) to (u c + v s, -u s + v c).
      lowest = std::min(lowest, terrain_height(x + u * c + v * s, z - u * s + v * c));
    }
  }
  return lowest;
}

struct Placement {
  std::string name;
  int mesh = -1;
  glm::dvec3 translation{0.0};
  double yaw_deg = 0.0;
  double scale = 1.0;
};

tinygltf::Node trs_node(const Placement& p) {
  tinygltf::Node node;
  node.name = p.name;
  node.mesh = p.mesh;
  node.translation = {p.translation.x, p.translation.y, p.translation.z};
  if (p.yaw_deg != 0.0) node.rotation = yaw_rotation(p.yaw_deg);
  if (p.scale != 1.0) node.scale = {p.scale, p.scale, p.scale};
  return node;
}

// Column-major 4x4 of a rotation about +Y followed by a translation.
std::vector<double> yaw_translate_matrix(double yaw_deg, const glm::dvec3& t) {
  const double c = std::cos(yaw_deg * kDegToRad), s = std::sin(yaw_deg * kDegToRad);
  return {c, 0.0, -s, 0.0, 0.0, 1.0, 0.0, 0.0, s, 0.0, c, 0.0, t.x, t.y, t.z, 1.0};
}

int add_terrain(GltfBuilder& gltf, const Materials& m, int detail, const glm::vec3& near_albedo) {
  tinygltf::Node terrain;
  terrain.name = "terrain";
  const int root = gltf.add_node(terrain);
  const std::vector<TerrainChunk> chunks = build_terrain(detail, near_albedo);
  for (size_t i = 0; i < chunks.size(); ++i) {
    const std::string name = std::string(chunks[i].far ? "terrain_far_" : "terrain_near_") + std::to_string(i);
    tinygltf::Primitive primitive = gltf.add_primitive(chunks[i].mesh);
    primitive.material = chunks[i].far ? m.terrain_far : m.ground;
    tinygltf::Node node;
    node.name = name;
    node.mesh = gltf.add_mesh(name, {primitive});
    gltf.add_child(root, gltf.add_node(node));
  }
  return root;
}

int add_village(GltfBuilder& gltf, const Materials& m) {
  // The village node is offset so its buildings are placed relative to (0, -60).
  const glm::dvec3 origin(0.0, 0.0, -60.0);
  tinygltf::Node village;
  village.name = "village";
  village.translation = {origin.x, origin.y, origin.z};
  const int root = gltf.add_node(village);

  constexpr float kHouseW = 10.0f, kHouseD = 8.0f, kHouseWall = 6.0f, kFoundation = 3.0f;
  tinygltf::Primitive house_walls = gltf.add_primitive(building_walls(kHouseW, kHouseD, kHouseWall, kFoundation, 3.5f));
  house_walls.material = m.facade;
  tinygltf::Primitive house_roof = gltf.add_primitive(gable_roof(kHouseW, kHouseD, kHouseWall, 3.5f, 0.5f, 0.2f));
  house_roof.material = m.roof_tiles;
  const int house = gltf.add_mesh("gabled_house", {house_walls, house_roof});

  const auto flat_roofed = [&](const std::string& name, float w, float d, float h) {
    tinygltf::Primitive walls = gltf.add_primitive(building_walls(w, d, h, kFoundation, 0.0f));
    walls.material = m.facade;
    MeshData slab = box(glm::vec3(w + 0.6f, 0.4f, d + 0.6f), 1.0f, false);
    for (glm::vec3& p : slab.positions) p.y += h + 0.2f;
    tinygltf::Primitive roof = gltf.add_primitive(slab);
    roof.material = m.concrete;
    return gltf.add_mesh(name, {walls, roof});
  };
  const int tower = flat_roofed("tower", 12.0f, 12.0f, 24.0f);
  const int block = flat_roofed("block", 20.0f, 10.0f, 9.0f);

  struct Building {
    const char* name;
    int mesh;
    double x, z, yaw_deg, scale, half_w, half_d;
  };
  const std::array<Building, 5> buildings{{
      {"house_a", house, -24.0, -56.0, 10.0, 1.0, 5.0, 4.0},
      {"house_b", house, 34.0, -52.0, 80.0, 1.0, 5.0, 4.0},
      {"house_c", house, -42.0, -96.0, -15.0, 1.2, 6.0, 4.8},
      {"tower", tower, 22.0, -100.0, 5.0, 1.0, 6.0, 6.0},
      {"block", block, -5.0, -140.0, 0.0, 1.0, 10.0, 5.0},
  }};
  for (const Building& b : buildings) {
    const double y = footprint_ground(b.x, b.z, b.half_w, b.half_d, b.yaw_deg);
    const Placement p{b.name, b.mesh, glm::dvec3(b.x, y, b.z) - origin, b.yaw_deg, b.scale};
    gltf.add_child(root, gltf.add_node(trs_node(p)));
  }
  return root;
}

int add_sign(GltfBuilder& gltf, const Materials& m, double x, double z) {
  constexpr float kWidth = 3.2f, kHeight = 0.8f, kBottom = 2.0f, kDepth = 0.1f;
  tinygltf::Node sign;
  sign.name = "emissive_sign";
  sign.matrix = yaw_translate_matrix(-15.0, glm::dvec3(x, terrain_height(x, z) - 0.1, z));
  const int root = gltf.add_node(sign);

  MeshData board = box(glm::vec3(kWidth + 0.1f, kHeight + 0.1f, kDepth), 1.0f, false);
  tinygltf::Primitive board_primitive = gltf.add_primitive(board);
  board_primitive.material = m.concrete;
  tinygltf::Primitive face = gltf.add_primitive(upright_quad(kWidth, kHeight, glm::vec2(kWidth, kHeight)));
  face.material = m.sign_face;
  tinygltf::Primitive post = gltf.add_primitive(box(glm::vec3(0.12f, kBottom + kHeight + 0.4f, 0.12f), 1.0f, false));
  post.material = m.steel;
  const int board_mesh = gltf.add_mesh("sign_board", {board_primitive});
  const int face_mesh = gltf.add_mesh("sign_face", {face});
  const int post_mesh = gltf.add_mesh("sign_post", {post});

  const double post_centre_y = 0.5 * (kBottom + kHeight + 0.4) - 0.4;  // 0.4 m in the ground
  const std::array<Placement, 4> parts{{
      {"sign_board", board_mesh, {0.0, kBottom + 0.5 * kHeight, 0.0}},
      {"sign_face", face_mesh, {0.0, kBottom, 0.5 * kDepth + 0.005}},
      {"sign_post_left", post_mesh, {-0.4 * kWidth, post_centre_y, -0.5 * kDepth - 0.06}},
      {"sign_post_right", post_mesh, {0.4 * kWidth, post_centre_y, -0.5 * kDepth - 0.06}},
  }};
  for (const Placement& p : parts) gltf.add_child(root, gltf.add_node(trs_node(p)));
  return root;
}

int add_props(GltfBuilder& gltf, const Materials& m) {
  tinygltf::Node props;
  props.name = "props";
  const int root = gltf.add_node(props);
  const auto place = [&](const Placement& p) { gltf.add_child(root, gltf.add_node(trs_node(p))); };

  // Two spheres share one set of accessors, each mesh with its own material.
  constexpr float kRadius = 1.2f;
  tinygltf::Primitive sphere = gltf.add_primitive(uv_sphere(kRadius, 48, 24));
  sphere.material = m.polished_metal;
  const int metal_sphere = gltf.add_mesh("sphere_polished_metal", {sphere});
  sphere.material = m.rough_clay;
  const int clay_sphere = gltf.add_mesh("sphere_rough_clay", {sphere});
  place({"sphere_metal", metal_sphere, {-4.0, terrain_height(-4.0, -24.0) + kRadius - 0.05, -24.0}});
  place({"sphere_clay", clay_sphere, {0.5, terrain_height(0.5, -24.0) + kRadius - 0.05, -24.0}});

  tinygltf::Primitive pane = gltf.add_primitive(upright_quad(2.4f, 2.0f, glm::vec2(2.4f, 2.0f)));
  pane.material = m.glass;
  place({"glass_pane", gltf.add_mesh("glass_pane", {pane}), {-4.0, terrain_height(-4.0, -20.0) + 0.3, -20.0}});

  // Its front faces away from the camera: only double-sided rendering shows it.
  tinygltf::Primitive wall = gltf.add_primitive(upright_quad(6.0f, 2.5f, glm::vec2(1.0f)));
  wall.material = m.thin_wall;
  place({"thin_wall", gltf.add_mesh("thin_wall", {wall}), {-14.0, terrain_height(-14.0, -34.0) - 0.2, -34.0}, 160.0});

  constexpr float kFenceLength = 24.0f, kFenceHeight = 1.5f;
  tinygltf::Primitive fence = gltf.add_primitive(upright_quad(kFenceLength, kFenceHeight, glm::vec2(kFenceHeight)));
  fence.material = m.fence;
  place({"fence", gltf.add_mesh("picket_fence", {fence}), {-18.0, terrain_height(-18.0, -40.0) - 0.1, -40.0}});

  tinygltf::Primitive cards = gltf.add_primitive(crossed_cards(5.0f, 7.0f));
  cards.material = m.foliage;
  const int tree = gltf.add_mesh("tree_cards", {cards});
  struct Tree { double x, z, yaw_deg, scale; };
  constexpr std::array<Tree, 7> trees{{{-22, -68, 20, 1.0},
                                       {14, -44, 65, 0.8},
                                       {44, -72, 10, 1.2},
                                       {-40, -78, 35, 1.1},
                                       {-10, -112, 50, 1.3},
                                       {42, -128, 5, 1.0},
                                       {-58, -46, 80, 0.9}}};
  for (size_t i = 0; i < trees.size(); ++i) {
    const Tree& t = trees[i];
    place({"tree_" + std::to_string(i), tree, {t.x, terrain_height(t.x, t.z) - 0.1, t.z}, t.yaw_deg, t.scale});
  }

  gltf.add_child(root, add_sign(gltf, m, 7.0, -28.0));
  return root;
}

// Quaternion turning the glTF camera's -Z towards `forward` with +Y up.
std::vector<double> look_rotation(const glm::dvec3& forward) {
  const glm::dvec3 z = -glm::normalize(forward);
  const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), z));
  const glm::dvec3 y = glm::cross(z, x);
  const glm::dquat q = glm::quat_cast(glm::dmat3(x, y, z));
  return {q.x, q.y, q.z, q.w};
}

int add_camera(GltfBuilder& gltf) {
  tinygltf::Camera camera;
  camera.name = "camera_main";
  camera.type = "perspective";
  camera.perspective.yfov = 60.0 * kDegToRad;
  camera.perspective.znear = 0.1;
  camera.perspective.zfar = 200000.0;  // beyond the terrain's far corner
  tinygltf::Node node;
  node.name = "camera_main";
  node.camera = gltf.add_camera(camera);
  const glm::dvec3 position(0.0, terrain_height(0.0, 14.0) + 5.5, 14.0);
  node.translation = {position.x, position.y, position.z};
  node.rotation = look_rotation(glm::dvec3(0.0, -0.04, -1.0));
  return gltf.add_node(node);
}

int add_sun(GltfBuilder& gltf) {
  tinygltf::Light light;
  light.name = "sun";
  light.type = "directional";
  light.color = {1.0, 1.0, 1.0};
  light.intensity = kSunIlluminanceLux;
  const int index = gltf.add_light(light);
  // A directional light shines along its node's -Z, so +Z points at the sun.
  const double az = kSunAzimuthDeg * kDegToRad, el = kSunElevationDeg * kDegToRad;
  const glm::dvec3 z(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), z));
  const glm::dvec3 y = glm::cross(z, x);
  tinygltf::Node node;
  node.name = "sun";
  node.matrix = {x.x, x.y, x.z, 0.0, y.x, y.y, y.z, 0.0, z.x, z.y, z.z, 0.0, 0.0, 100.0, 0.0, 1.0};
  tinygltf::Value::Object ext;
  ext["light"] = tinygltf::Value(index);
  node.extensions["KHR_lights_punctual"] = tinygltf::Value(ext);
  return gltf.add_node(node);
}

}  // namespace

tinygltf::Model build_default_scene(int detail) {
  GltfBuilder gltf;
  const ImageRGBA8 ground_color = ground_base_color();
  const Materials materials = add_materials(gltf, ground_color);
  tinygltf::Node world;
  world.name = "world";
  const int root = gltf.add_node(world);
  gltf.add_root_node(root);
  gltf.add_child(root, add_terrain(gltf, materials, detail, mean_linear_color(ground_color)));
  gltf.add_child(root, add_village(gltf, materials));
  gltf.add_child(root, add_props(gltf, materials));
  gltf.add_child(root, add_camera(gltf));
  gltf.add_child(root, add_sun(gltf));
  return std::move(gltf.model());
}

}  // namespace cr::gen

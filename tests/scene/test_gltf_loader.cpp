// glTF loading: file flavours, primitive modes, index types, transforms,
// generated normals/tangents, materials, cameras, sun, missing images.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/gltf_test_builder.h"
#include "tests/khronos_assets.h"

namespace {

using cr::test::GltfBuilder;

const std::string kAssimp = CR_ASSIMP_GLTF_DIR;
const std::string kBad = std::string(CR_TEST_DATA_DIR) + "/bad";

bool close(const glm::mat4& a, const glm::mat4& b, float eps = 1e-5f) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(a[c][r] - b[c][r]) > eps) return false;
  return true;
}

// World-space triangles of a scene, as flat vertex triples.
std::vector<glm::vec3> world_triangles(const cr::Scene& s) {
  std::vector<glm::vec3> out;
  for (const cr::Draw& d : s.draws) {
    const cr::Primitive& p = s.primitive(d);
    for (uint32_t i : p.indices) out.push_back(glm::vec3(d.world * glm::vec4(p.positions[i], 1.0f)));
  }
  return out;
}

// A single-node scene drawing one mesh made of `primitive`.
void single_mesh_scene(GltfBuilder& b, nlohmann::json primitive) {
  b.add("meshes", {{"primitives", nlohmann::json::array({primitive})}});
  b.add("nodes", {{"mesh", 0}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
}

}  // namespace

TEST_CASE("glTF with external buffers, embedded buffers and GLB give the same scene") {
  cr::Scene ext = cr::load_gltf(kAssimp + "/BoxTextured-glTF/BoxTextured.gltf");
  cr::Scene emb = cr::load_gltf(kAssimp + "/BoxTextured-glTF-Embedded/BoxTextured.gltf");
  cr::Scene glb = cr::load_gltf(kAssimp + "/BoxTextured-glTF-Binary/BoxTextured.glb");
  for (const cr::Scene* s : {&emb, &glb}) {
    REQUIRE(s->draws.size() == ext.draws.size());
    REQUIRE(s->draws.size() == 1);
    CHECK(close(s->draws[0].world, ext.draws[0].world));
    const cr::Primitive& a = ext.primitive(ext.draws[0]);
    const cr::Primitive& b = s->primitive(s->draws[0]);
    CHECK(a.positions == b.positions);
    CHECK(a.normals == b.normals);
    CHECK(a.texcoords == b.texcoords);
    CHECK(a.indices == b.indices);
    REQUIRE(s->images.size() == 1);
    CHECK(s->images[0].mips[0].rgba == ext.images[0].mips[0].rgba);
  }
  CHECK(ext.triangle_count() == 12);
  CHECK(ext.images[0].srgb);  // used as base colour
  CHECK(ext.materials.at(0).base_color.valid());
}

TEST_CASE("triangle strips and fans become triangle lists with the same winding") {
  const std::string dir = kAssimp + "/glTF-Asset-Generator/Mesh_PrimitiveMode/";
  cr::Scene list = cr::load_gltf(dir + "Mesh_PrimitiveMode_06.gltf");
  std::vector<glm::vec3> ref = world_triangles(list);
  REQUIRE(ref.size() == 6);
  auto area_normal = [](const std::vector<glm::vec3>& t) {
    glm::vec3 n(0.0f);
    for (size_t i = 0; i < t.size(); i += 3) n += glm::cross(t[i + 1] - t[i], t[i + 2] - t[i]);
    return n;
  };
  glm::vec3 ref_n = area_normal(ref);
  for (const char* f : {"04", "05", "11", "12"}) {  // strip, fan, indexed strip, indexed fan
    CAPTURE(f);
    cr::Scene s = cr::load_gltf(dir + "Mesh_PrimitiveMode_" + f + ".gltf");
    CHECK(s.triangle_count() == 2);
    glm::vec3 n = area_normal(world_triangles(s));
    CHECK(glm::length(n - ref_n) < 1e-5f);  // same total area, same facing
  }
  // Points and lines load without error and are not drawn.
  for (const char* f : {"00", "01", "02", "03", "07", "08", "09", "10"}) {
    CAPTURE(f);
    CHECK(cr::load_gltf(dir + "Mesh_PrimitiveMode_" + f + ".gltf").draws.empty());
  }
}

TEST_CASE("8, 16 and 32-bit indices load to the same triangles") {
  const std::string dir = kAssimp + "/glTF-Asset-Generator/Mesh_PrimitiveMode/";
  std::vector<uint32_t> expected = {1, 0, 3, 1, 3, 2};
  for (const char* f : {"13", "14", "15"}) {  // UNSIGNED_INT, UNSIGNED_BYTE, UNSIGNED_SHORT
    CAPTURE(f);
    cr::Scene s = cr::load_gltf(dir + "Mesh_PrimitiveMode_" + f + ".gltf");
    REQUIRE(s.draws.size() == 1);
    CHECK(s.primitive(s.draws[0]).indices == expected);
  }
  // The same through the builder, with every index width on one mesh.
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  int i8 = b.indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3});
  int i16 = b.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  int i32 = b.indices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
  nlohmann::json prims = nlohmann::json::array();
  for (int idx : {i8, i16, i32}) prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
  b.add("meshes", {{"primitives", prims}});
  b.add("nodes", {{"mesh", 0}});
  cr::Scene s = cr::load_gltf(b.write("index_widths.gltf"));
  REQUIRE(s.draws.size() == 3);
  for (const cr::Draw& d : s.draws) CHECK(s.primitive(d).indices == std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
}

TEST_CASE("TRS and matrix nodes give the same world matrices, and mirroring is flagged") {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  glm::vec3 t(1.0f, -2.0f, 3.5f), sc(2.0f, 0.5f, 1.5f);
  glm::quat q = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f)));
  glm::mat4 local = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(q) * glm::scale(glm::mat4(1.0f), sc);
  glm::mat4 parent = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 10.0f, 0.0f)) *
                     glm::rotate(glm::mat4(1.0f), 1.2f, glm::vec3(0.0f, 1.0f, 0.0f));
  std::vector<float> local_m(glm::value_ptr(local), glm::value_ptr(local) + 16);
  std::vector<float> parent_m(glm::value_ptr(parent), glm::value_ptr(parent) + 16);
  // Node 0: parent (matrix) of node 1 (TRS) and node 2 (matrix); node 3: mirrored.
  b.add("nodes", {{"matrix", parent_m}, {"children", {1, 2}}});
  b.add("nodes", {{"mesh", 0}, {"translation", {t.x, t.y, t.z}}, {"rotation", {q.x, q.y, q.z, q.w}},
                  {"scale", {sc.x, sc.y, sc.z}}});
  b.add("nodes", {{"mesh", 0}, {"matrix", local_m}});
  b.add("nodes", {{"mesh", 0}, {"scale", {-1.0, 1.0, 1.0}}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0, 3}}}});
  cr::Scene s = cr::load_gltf(b.write("transforms.gltf"));
  REQUIRE(s.draws.size() == 3);
  glm::mat4 expected = parent * local;
  CHECK(close(s.draws[0].world, expected, 1e-4f));
  CHECK(close(s.draws[1].world, expected, 1e-4f));
  CHECK_FALSE(s.draws[0].mirrored);
  CHECK(s.draws[2].mirrored);
  // Normal matrix: inverse transpose of the upper 3x3.
  glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(expected)));
  for (int c = 0; c < 3; ++c) CHECK(glm::length(s.draws[0].normal_matrix[c] - nm[c]) < 1e-4f);
  // World bounds contain every transformed vertex.
  for (const cr::Draw& d : s.draws) {
    for (const glm::vec3& p : s.primitive(d).positions) {
      glm::vec3 w(d.world * glm::vec4(p, 1.0f));
      CHECK(glm::all(glm::greaterThanEqual(w, d.world_bounds_min - 1e-4f)));
      CHECK(glm::all(glm::lessThanEqual(w, d.world_bounds_max + 1e-4f)));
      CHECK(glm::all(glm::greaterThanEqual(w, s.bounds_min - 1e-4f)));
    }
  }
}

TEST_CASE("generated normals are unit length and point out of a closed box") {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  cr::test::unit_cube(positions, indices);
  GltfBuilder b;
  int pos = b.floats(positions, "VEC3", 3);
  int idx = b.indices(indices);
  single_mesh_scene(b, {{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
  cr::Scene s = cr::load_gltf(b.write("box_no_normals.gltf"));
  REQUIRE(s.draws.size() == 1);
  const cr::Primitive& p = s.primitive(s.draws[0]);
  REQUIRE(p.normals.size() == 24);
  for (size_t v = 0; v < 24; ++v) {
    const glm::vec3& n = p.normals[v];
    CHECK(std::abs(glm::length(n) - 1.0f) < 1e-5f);
    // Vertices are not shared between faces: each normal is its face's outward axis.
    CHECK(std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)}) == doctest::Approx(1.0));
    CHECK(glm::dot(n, p.positions[v]) == doctest::Approx(0.5));
  }
  CHECK(p.tangents.empty());  // no normal map, no tangents
}

TEST_CASE("bad normals (BoxBadNormals) are replaced by generated ones") {
  cr::Scene s = cr::load_gltf(kAssimp + "/BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
  REQUIRE(s.draws.size() == 1);
  const cr::Primitive& p = s.primitive(s.draws[0]);
  glm::vec3 centre = 0.5f * (p.bounds_min + p.bounds_max);
  for (size_t v = 0; v < p.normals.size(); ++v) {
    CHECK(std::abs(glm::length(p.normals[v]) - 1.0f) < 1e-5f);
    CHECK(glm::dot(p.normals[v], p.positions[v] - centre) > 0.0f);
  }
}

TEST_CASE("tangents are generated for normal-mapped materials, orthogonal to the normals") {
  // A quad in the XY plane with U along +X and V along -Y (the image's top up).
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  int uv = b.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2);
  int idx = b.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  b.add("images", {{"uri", cr::test::kFlatNormalPng}});
  b.add("textures", {{"source", 0}});
  b.add("materials", {{"normalTexture", {{"index", 0}, {"scale", 0.5}}}});
  single_mesh_scene(b, {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", idx}, {"material", 0}});
  cr::Scene s = cr::load_gltf(b.write("normal_mapped_quad.gltf"));
  const cr::Primitive& p = s.primitive(s.draws.at(0));
  REQUIRE(p.tangents.size() == 4);
  for (size_t v = 0; v < 4; ++v) {
    glm::vec3 t(p.tangents[v]);
    CHECK(std::abs(glm::length(t) - 1.0f) < 1e-5f);
    CHECK(std::abs(glm::dot(t, p.normals[v])) < 1e-5f);
    CHECK(glm::dot(t, glm::vec3(1.0f, 0.0f, 0.0f)) > 0.999f);  // along +U
    // V runs along -Y, so the image's top (decreasing v) is +Y = cross(N, T): w = +1.
    CHECK(p.tangents[v].w == 1.0f);
  }
  const cr::Material& m = s.materials.at(0);
  REQUIRE(m.normal.valid());
  CHECK(m.normal.scale == 0.5f);
  CHECK_FALSE(s.images.at(m.normal.image).srgb);
  CHECK(s.images.at(m.normal.image).mips.size() == 1);  // 1x1
}

TEST_CASE("materials, samplers and image colour spaces are converted") {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  int uv = b.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  b.add("images", {{"uri", cr::test::kFlatNormalPng}});
  b.add("samplers", {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9986}});
  b.add("samplers", {{"minFilter", 9729}});
  b.add("textures", {{"source", 0}, {"sampler", 0}});
  b.add("textures", {{"source", 0}, {"sampler", 1}});
  b.add("materials", {{"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}}, {"baseColorTexture", {{"index", 0}}},
                        {"metallicFactor", 0.2}, {"roughnessFactor", 0.8},
                        {"metallicRoughnessTexture", {{"index", 1}}}}},
                      {"occlusionTexture", {{"index", 1}, {"strength", 0.25}}},
                      {"emissiveTexture", {{"index", 0}}},
                      {"emissiveFactor", {1.0, 0.5, 0.0}},
                      {"alphaMode", "MASK"},
                      {"alphaCutoff", 0.3},
                      {"doubleSided", true}});
  single_mesh_scene(b, {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 0}});
  cr::Scene s = cr::load_gltf(b.write("materials.gltf"));
  REQUIRE(s.samplers.size() == 2);
  CHECK(s.samplers[0].wrap_s == cr::Wrap::ClampToEdge);
  CHECK(s.samplers[0].wrap_t == cr::Wrap::MirroredRepeat);
  CHECK(s.samplers[0].mag == cr::Filter::Nearest);
  CHECK(s.samplers[0].min == cr::Filter::Nearest);
  CHECK(s.samplers[0].mip == cr::Filter::Linear);
  CHECK(s.samplers[1].wrap_s == cr::Wrap::Repeat);
  CHECK(s.samplers[1].min == cr::Filter::Linear);
  CHECK_FALSE(s.samplers[1].mip.has_value());
  const cr::Material& m = s.materials.at(0);
  CHECK(m.base_color_factor == glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  CHECK(m.metallic_factor == doctest::Approx(0.2));
  CHECK(m.roughness_factor == doctest::Approx(0.8));
  CHECK(m.emissive_factor == glm::vec3(1.0f, 0.5f, 0.0f));
  CHECK(m.alpha_mode == cr::AlphaMode::Mask);
  CHECK(m.alpha_cutoff == doctest::Approx(0.3));
  CHECK(m.double_sided);
  CHECK(m.occlusion.scale == 0.25f);
  CHECK(m.base_color.sampler == 0);
  CHECK(m.metallic_roughness.sampler == 1);
  // One glTF image used as sRGB (base colour, emissive) and linear (metal-rough,
  // occlusion): two scene images, shared within each colour space.
  REQUIRE(s.images.size() == 2);
  CHECK(m.base_color.image == m.emissive.image);
  CHECK(m.metallic_roughness.image == m.occlusion.image);
  CHECK(s.images[m.base_color.image].srgb);
  CHECK_FALSE(s.images[m.metallic_roughness.image].srgb);
  CHECK(s.images[0].mips[0].rgba == std::vector<uint8_t>{128, 128, 255, 255});
}

TEST_CASE("perspective cameras and the KHR_lights_punctual sun are placed by their nodes") {
  GltfBuilder b;
  b.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.05}, {"aspectRatio", 1.5}}}});
  b.add("cameras", {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "directional"}, {"intensity", 3.0}, {"color", {1.0, 0.9, 0.8}}}}}}}};
  // Camera at (0, 2, 10) turned 90 degrees left (about +Y): looks along -X.
  glm::quat yaw = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  b.add("nodes", {{"camera", 0}, {"translation", {0.0, 2.0, 10.0}}, {"rotation", {yaw.x, yaw.y, yaw.z, yaw.w}}});
  b.add("nodes", {{"camera", 1}});
  // Light pitched -90 degrees about X: it shines straight down, the sun is overhead.
  glm::quat pitch = glm::angleAxis(glm::radians(-90.0f), glm::vec3(1, 0, 0));
  b.add("nodes", {{"rotation", {pitch.x, pitch.y, pitch.z, pitch.w}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0, 1, 2}}}});
  cr::Scene s = cr::load_gltf(b.write("camera_and_sun.gltf"));
  REQUIRE(s.cameras.size() == 2);  // perspective and orthographic, in traversal order
  CHECK(s.cameras[1].orthographic);
  CHECK(s.cameras[1].zfar == 10.0f);
  const cr::GltfCamera& c = s.cameras[0];
  CHECK_FALSE(c.orthographic);
  CHECK(glm::length(c.position - glm::vec3(0, 2, 10)) < 1e-5f);
  CHECK(glm::length(c.forward - glm::vec3(-1, 0, 0)) < 1e-5f);
  CHECK(glm::length(c.up - glm::vec3(0, 1, 0)) < 1e-5f);
  CHECK(c.yfov_rad == doctest::Approx(0.6));
  CHECK(c.znear == doctest::Approx(0.05));
  CHECK(c.aspect.value_or(0.0f) == doctest::Approx(1.5));
  REQUIRE(s.sun.has_value());
  CHECK(glm::length(s.sun->direction_to_sun - glm::vec3(0, 1, 0)) < 1e-5f);
  CHECK(s.sun->intensity == 3.0f);
  CHECK(s.sun->color == glm::vec3(1.0f, 0.9f, 0.8f));

  cr::Scene cams = cr::load_gltf(kAssimp + "/cameras/Cameras.gltf");
  REQUIRE(cams.cameras.size() == 2);
  CHECK_FALSE(cams.cameras[0].orthographic);
  CHECK(cams.cameras[1].orthographic);
}

TEST_CASE("scene selection: the default scene, else scene 0, else every root node") {
  GltfBuilder b;
  int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.add("nodes", {{"mesh", 0}, {"children", {1}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("nodes", {{"mesh", 0}});
  CHECK(cr::load_gltf(b.write("no_scenes.gltf")).draws.size() == 3);  // roots 0 (with child 1) and 2
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {2}}}, {{"nodes", {0}}}});
  CHECK(cr::load_gltf(b.write("scene_zero.gltf")).draws.size() == 1);
  b.doc["scene"] = 1;
  CHECK(cr::load_gltf(b.write("scene_one.gltf")).draws.size() == 2);
  b.doc["scene"] = 2;
  CHECK_THROWS_AS(cr::load_gltf(b.write("scene_two.gltf")), cr::InputError);
}

TEST_CASE("missing image files: an error listing them, or dropped textures when allowed") {
  const std::string path = kBad + "/missing_image.gltf";
  try {
    cr::load_gltf(path);
    FAIL("expected InputError");
  } catch (const cr::InputError& e) {
    CHECK(e.file() == path);
    CHECK(std::string(e.what()).find("no_such_texture.png") != std::string::npos);
  }
  cr::GltfLoadOptions allow;
  allow.allow_missing_images = true;
  cr::Scene s = cr::load_gltf(path, allow);
  CHECK(s.images.empty());
  CHECK_FALSE(s.materials.at(0).base_color.valid());
  CHECK(s.draws.size() == 1);
}

TEST_CASE("FlightHelmet with its three missing textures (CR_ASSETS_DIR)") {
  const auto found = cr::test::asset_path("FlightHelmet/glTF/FlightHelmet.gltf");
  if (!found) return;
  const std::string& path = *found;
  try {
    cr::load_gltf(path);
    FAIL("expected InputError");
  } catch (const cr::InputError& e) {
    std::string what = e.what();
    CHECK(e.file() == path);
    for (const char* missing : {"FlightHelmet_Materials_LeatherPartsMat_BaseColor.png",
                                "FlightHelmet_Materials_LeatherPartsMat_Normal.png",
                                "FlightHelmet_Materials_LeatherPartsMat_OcclusionRoughMetal.png"}) {
      CHECK(what.find(missing) != std::string::npos);
    }
  }
  cr::GltfLoadOptions allow;
  allow.allow_missing_images = true;
  cr::Scene s = cr::load_gltf(path, allow);
  CHECK(s.triangle_count() == 94722);
  bool leather_found = false;
  for (const cr::Material& m : s.materials) {
    if (m.name == "LeatherPartsMat") {
      leather_found = true;
      CHECK_FALSE(m.base_color.valid());
      CHECK_FALSE(m.normal.valid());
    } else {
      CHECK(m.base_color.valid());
    }
  }
  CHECK(leather_found);
  for (const cr::Image& img : s.images) {
    CHECK(img.mips.back().width == 1);
    CHECK(img.mips.back().height == 1);
  }
}

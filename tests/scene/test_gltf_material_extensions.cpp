// Material extensions at load: KHR_texture_transform (per texture reference,
// with its texCoord override), TEXCOORD_1 per texture,
// KHR_materials_emissive_strength and KHR_materials_unlit; their values
// validated. Khronos sample models come from CR_ASSETS_DIR (skipped without).
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "engine/scene/gltf_loader.h"
#include "tests/khronos_assets.h"
#include "tests/scene/expect_gltf_rejected.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

using cr::test::GltfBuilder;

const cr::Material& material_named(const cr::Scene& s, const std::string& name) {
  for (const cr::Material& m : s.materials)
    if (m.name == name) return m;
  FAIL("no material " << name);
  return s.materials.front();
}

// A triangle with TEXCOORD_0 (and TEXCOORD_1 when asked) whose material is `material`.
std::string textured_triangle(const std::string& name, const nlohmann::json& material, bool uv1 = true) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int uv0 = b.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  nlohmann::json attributes = {{"POSITION", pos}, {"TEXCOORD_0", uv0}};
  if (uv1) attributes["TEXCOORD_1"] = b.floats({0.5f, 0.5f, 1, 0.5f, 0.5f, 1}, "VEC2", 2);
  b.add("images", {{"uri", cr::test::kFlatNormalPng}});
  b.add("textures", {{"source", 0}});
  b.add("materials", material);
  b.add("meshes", {{"primitives", {{{"attributes", attributes}, {"material", 0}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
  return b.write(name);
}

nlohmann::json base_colour_with(const nlohmann::json& texture_info) {
  return {{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}};
}

nlohmann::json transform(const nlohmann::json& values) {
  return {{"index", 0}, {"extensions", {{"KHR_texture_transform", values}}}};
}

}  // namespace

TEST_CASE("KHR_texture_transform: offset, rotation, scale and the texCoord override are loaded") {
  const cr::Scene s = cr::load_gltf(textured_triangle(
      "texture_transform.gltf",
      {{"pbrMetallicRoughness",
        {{"baseColorTexture", transform({{"offset", {0.5, -0.25}}, {"rotation", 0.75}, {"scale", {2, 3}}})},
         {"metallicRoughnessTexture",
          {{"index", 0}, {"texCoord", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}}},
       {"emissiveTexture", {{"index", 0}, {"texCoord", 1}}},
       {"emissiveFactor", {1, 1, 1}}}));
  const cr::Material& m = s.materials.at(0);
  CHECK(m.base_color.transform.offset == glm::vec2(0.5f, -0.25f));
  CHECK(m.base_color.transform.rotation == 0.75f);
  CHECK(m.base_color.transform.scale == glm::vec2(2.0f, 3.0f));
  CHECK(m.base_color.texcoord == 0);
  CHECK(m.metallic_roughness.texcoord == 1);  // the override wins
  CHECK(m.metallic_roughness.transform.identity());
  CHECK(m.emissive.texcoord == 1);
  CHECK(m.emissive.transform.identity());
  const cr::Primitive& p = s.primitive(s.draws.at(0));
  REQUIRE(p.texcoords1.size() == 3);
  CHECK(p.texcoords1[1] == glm::vec2(1.0f, 0.5f));
}

TEST_CASE("texture coordinate sets above 1 fall back to TEXCOORD_0 with a warning") {
  const cr::Scene s = cr::load_gltf(textured_triangle(
      "texcoord_2.gltf", base_colour_with({{"index", 0}, {"texCoord", 2}}), false));
  CHECK(s.materials.at(0).base_color.texcoord == 0);
  CHECK(s.materials.at(0).base_color.valid());
  const cr::Scene o = cr::load_gltf(
      textured_triangle("texcoord_override_3.gltf", base_colour_with(transform({{"texCoord", 3}})), false));
  CHECK(o.materials.at(0).base_color.texcoord == 0);
}

TEST_CASE("KHR_texture_transform and texture coordinate sets: bad values are rejected naming them") {
  struct BadCase {
    nlohmann::json material;
    const char* fault;
  };
  const BadCase cases[] = {
      {base_colour_with(transform({{"offset", {1, 2, 3}}})), "KHR_texture_transform offset must be an array of 2 numbers"},
      {base_colour_with(transform({{"offset", {0, "x"}}})), "KHR_texture_transform offset[1] must be a number"},
      {base_colour_with(transform({{"rotation", "half"}})), "KHR_texture_transform rotation must be a number"},
      {base_colour_with(transform({{"scale", {1e300, 1}}})), "KHR_texture_transform scale[0] is"},
      {base_colour_with(transform({{"texCoord", 1.5}})), "KHR_texture_transform texCoord must be an integer"},
      {base_colour_with(transform({{"texCoord", -1}})), "texCoord -1 is negative"},
      {{{"emissiveFactor", {1, 1, 1}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -2}}}}}},
       "emissiveStrength is -2"},
      {{{"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e300}}}}}},
       "emissiveStrength is"},
  };
  int k = 0;
  for (const BadCase& c : cases) {
    CAPTURE(c.fault);
    expect_gltf_rejected(textured_triangle("bad_material_extension_" + std::to_string(k++) + ".gltf", c.material),
                         c.fault);
  }
  // A texture reading TEXCOORD_1 of a primitive without it.
  expect_gltf_rejected(textured_triangle("missing_texcoord_1.gltf", base_colour_with(transform({{"texCoord", 1}})),
                                         false),
                       "no TEXCOORD_1");
}

TEST_CASE("KHR_materials_emissive_strength and KHR_materials_unlit are loaded") {
  const cr::Scene s = cr::load_gltf(textured_triangle(
      "emissive_strength_unlit.gltf",
      {{"emissiveFactor", {0.5, 1, 0}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 12.5}}}, {"KHR_materials_unlit", nlohmann::json::object()}}}}));
  const cr::Material& m = s.materials.at(0);
  CHECK(m.emissive_strength == 12.5f);
  CHECK(m.emissive_factor == glm::vec3(0.5f, 1.0f, 0.0f));
  CHECK(m.unlit);
  const cr::Scene plain = cr::load_gltf(textured_triangle("plain_material.gltf", base_colour_with({{"index", 0}})));
  CHECK(plain.materials.at(0).emissive_strength == 1.0f);
  CHECK_FALSE(plain.materials.at(0).unlit);
}

TEST_CASE("Khronos TextureTransformTest and TextureTransformMultiTest: transforms and UV sets per slot (CR_ASSETS_DIR)") {
  const auto single = cr::test::asset_path("khronos/TextureTransformTest/glTF/TextureTransformTest.gltf");
  const auto multi = cr::test::asset_path("khronos/TextureTransformMultiTest/glTF/TextureTransformMultiTest.gltf");
  if (!single || !multi) return;
  const cr::Scene s = cr::load_gltf(*single);
  CHECK(material_named(s, "Offset U").base_color.transform.offset == glm::vec2(0.5f, 0.0f));
  CHECK(material_named(s, "Offset V").base_color.transform.offset == glm::vec2(0.0f, 0.5f));
  CHECK(material_named(s, "Rotation").base_color.transform.rotation == doctest::Approx(0.39269908));
  CHECK(material_named(s, "Scale").base_color.transform.scale == glm::vec2(1.5f));
  const cr::UvTransform all = material_named(s, "All").base_color.transform;
  CHECK(all.offset == glm::vec2(-0.2f, -0.1f));
  CHECK(all.rotation == 0.3f);
  CHECK(all.scale == glm::vec2(1.5f));
  CHECK(material_named(s, "Correct").base_color.transform.identity());

  // Required KHR_texture_transform; every input in a TEXCOORD_0 and a TEXCOORD_1 variant.
  const cr::Scene m = cr::load_gltf(*multi);
  CHECK(material_named(m, "BaseColorTest1Mat").base_color.texcoord == 1);
  CHECK(material_named(m, "BaseColorTest0Mat").base_color.texcoord == 0);
  CHECK(material_named(m, "EmissionTest1Mat").emissive.texcoord == 1);
  CHECK(material_named(m, "NormalTest1Mat").normal.texcoord == 1);
  CHECK(material_named(m, "MetalRoughTest1Mat").metallic_roughness.texcoord == 1);
  CHECK(material_named(m, "OcclusionTest1Mat").occlusion.texcoord == 1);
  CHECK(material_named(m, "UnlitTest1Mat").unlit);
  CHECK(material_named(m, "NormalTest1Mat").normal.transform.rotation == doctest::Approx(1.5707963));
  CHECK(material_named(m, "NormalSampleMat").normal.transform.identity());
  // The primitives of the six inputs read here through TEXCOORD_1 (clearcoat is not read) have it.
  size_t reading_uv1 = 0;
  for (const cr::Draw& d : m.draws) {
    const cr::Primitive& p = m.primitive(d);
    const cr::Material& mat = m.materials.at(size_t(p.material));
    if (mat.base_color.texcoord + mat.metallic_roughness.texcoord + mat.normal.texcoord + mat.occlusion.texcoord +
            mat.emissive.texcoord == 0)
      continue;
    ++reading_uv1;
    CHECK(p.texcoords1.size() == p.positions.size());
  }
  CHECK(reading_uv1 == 6);
}

TEST_CASE("Khronos MultiUVTest, EmissiveStrengthTest and UnlitTest: their extensions and UV sets (CR_ASSETS_DIR)") {
  const auto multi_uv = cr::test::asset_path("khronos/MultiUVTest/glTF/MultiUVTest.gltf");
  const auto emissive = cr::test::asset_path("khronos/EmissiveStrengthTest/glTF/EmissiveStrengthTest.gltf");
  const auto unlit = cr::test::asset_path("khronos/UnlitTest/glTF/UnlitTest.gltf");
  if (!multi_uv || !emissive || !unlit) return;
  const cr::Scene uv = cr::load_gltf(*multi_uv);
  CHECK(uv.materials.at(0).base_color.texcoord == 0);
  CHECK(uv.materials.at(0).emissive.texcoord == 1);
  CHECK_FALSE(uv.primitive(uv.draws.at(0)).texcoords1.empty());

  const cr::Scene e = cr::load_gltf(*emissive);
  for (const int strength : {1, 2, 4, 8, 16}) {
    const cr::Material& m = material_named(e, "Emit" + std::to_string(strength));
    CHECK(m.emissive_strength == float(strength));
    CHECK(m.emissive_factor == glm::vec3(0.1f, 0.5f, 0.9f));
  }

  const cr::Scene u = cr::load_gltf(*unlit);  // KHR_materials_unlit is required
  REQUIRE(u.materials.size() == 2);
  for (const cr::Material& m : u.materials) CHECK(m.unlit);
}

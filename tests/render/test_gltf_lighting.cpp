// glTF materials and lights as whole frames show them: KHR_texture_transform
// and TEXCOORD_1 (Khronos TextureTransformTest, TextureTransformMultiTest,
// MultiUVTest), the emissive convention with KHR_materials_emissive_strength
// (EmissiveStrengthTest), KHR_materials_unlit (UnlitTest), and point and spot
// lights against their closed forms. Khronos models come from CR_ASSETS_DIR
// (skipped without).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/luminance.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"
#include "engine/shading/brdf.h"
#include "engine/shading/punctual_lights.h"
#include "tests/khronos_assets.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

// A frame rendered by the engine alone (no plugins) and the camera it used.
struct Frame {
  int width = 0, height = 0;
  cr::Camera camera;
  std::vector<glm::vec3> color;
  std::vector<uint8_t> edge;  // pixels resolved from several surfaces (anti-aliased edges)
  const glm::vec3& at(int x, int y) const { return color[size_t(y) * size_t(width) + size_t(x)]; }
};

Frame render(const cr::Scene& scene, const std::string& name, const nlohmann::json& description, int w, int h) {
  const std::string file = std::string(CR_BINARY_DIR) + "/gltf_lighting_" + name + ".json";
  std::ofstream(file) << description.dump();
  const cr::SceneDescription d = cr::load_scene_description(file, {});
  cr::Profile profile = cr::load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  profile.width = w;
  profile.height = h;
  cr::JobSystem jobs(2);
  cr::Renderer r(scene, d, profile, {}, jobs);
  r.render_frame(0);
  std::vector<uint8_t> edge(size_t(w) * size_t(h), 0);
  for (const cr::EdgeFragment& e : r.buffers().fragments) edge[e.pixel] = 1;
  return {w, h, r.frame_view(0).camera, r.buffers().color, std::move(edge)};
}

// A scene description for `gltf` seen from `position` towards `target`, lit
// by `ambient` radiance and a sun of `sun_lux` (0: none).
nlohmann::json view(const std::string& gltf, glm::vec3 position, glm::vec3 target, float vfov_deg, float ambient,
                    float sun_lux = 0.0f, float ev100 = 15.0f) {
  return {{"gltf", gltf},
          {"camera", {{"position", {position.x, position.y, position.z}},
                      {"target", {target.x, target.y, target.z}},
                      {"vfov_deg", vfov_deg}}},
          {"sun", {{"azimuth_deg", -30}, {"elevation_deg", 40}, {"illuminance", sun_lux}}},
          {"ambient", {ambient, ambient, ambient}},
          {"exposure_ev100", ev100}};
}

// The world point where the ray through pixel (x, y)'s centre meets the
// plane dot(n, p) = c.
glm::vec3 on_plane(const Frame& f, int x, int y, glm::vec3 n, float c) {
  const float t = std::tan(0.5f * f.camera.vfov_rad);
  const float sx = (2.0f * (float(x) + 0.5f) / float(f.width) - 1.0f) * t * f.camera.aspect;
  const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(f.height)) * t;
  const glm::vec3 dir = f.camera.forward + sx * f.camera.right + sy * f.camera.up;
  const glm::vec3 origin(f.camera.position);
  return origin + dir * ((c - glm::dot(n, origin)) / glm::dot(n, dir));
}

// Pixels whose point on the plane z = 0 lies in the square of half size
// `half` around `centre`, as (pixel, local offset from the centre).
template <typename Visit>
void for_square(const Frame& f, glm::vec2 centre, float half, const Visit& visit) {
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::vec3 p = on_plane(f, x, y, {0.0f, 0.0f, 1.0f}, 0.0f);
      const glm::vec2 local = glm::vec2(p) - centre;
      if (std::abs(local.x) < half && std::abs(local.y) < half) visit(f.at(x, y), local);
    }
}

glm::vec3 mean_colour(const Frame& f, glm::vec2 centre, float half) {
  glm::dvec3 sum(0.0);
  int n = 0;
  for_square(f, centre, half, [&](const glm::vec3& c, glm::vec2) {
    sum += glm::dvec3(c);
    ++n;
  });
  return glm::vec3(sum / double(std::max(n, 1)));
}

// Where the dark texels of the arrow lie on a TextureTransformTest quad of
// centre `centre`: their centroid relative to the quad's UV origin (its top
// left corner), as (angle in degrees from +x, distance in quad widths).
glm::vec2 arrow_centroid(const Frame& f, glm::vec2 centre) {
  glm::dvec2 sum(0.0);
  int n = 0;
  for_square(f, centre, 0.5f, [&](const glm::vec3& c, glm::vec2 local) {
    if (std::max({c.r, c.g, c.b}) > 1000.0f) return;  // white, grey border and markers: a channel above 1000
    sum += glm::dvec2(local - glm::vec2(-0.5f, 0.5f));
    ++n;
  });
  REQUIRE(n > 200);
  const glm::vec2 m(sum / double(n));
  return {glm::degrees(std::atan2(m.y, m.x)), glm::length(m)};
}

}  // namespace

TEST_CASE("TextureTransformTest: offsets pick their quadrant, the arrows point at the green markers (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/TextureTransformTest/glTF/TextureTransformTest.gltf");
  if (!path) return;
  cr::Scene scene = cr::load_gltf(*path);
  const nlohmann::json d = view(*path, {0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 40.0f, 4000.0f);
  const Frame f = render(scene, "texture_transform", d, 640, 480);
  // UV (0..0.5)^2 is the yellow "not supported" quadrant; offsets move it to
  // the green U, blue V and cyan UV ones.
  const glm::vec3 u = mean_colour(f, {-1.1f, 0.55f}, 0.3f), v = mean_colour(f, {0.0f, 0.55f}, 0.3f),
                  uv = mean_colour(f, {1.1f, 0.55f}, 0.3f);
  CHECK(u.g > 1.5f * u.r);
  CHECK(u.g > 1.5f * u.b);
  CHECK(v.b > 1.5f * v.r);
  CHECK(v.b > 1.5f * v.g);
  CHECK(uv.g > 1.5f * uv.r);
  CHECK(uv.b > 1.5f * uv.r);
  // The arrow's centroid lies at UV (0.40, 0.40) of Arrow.png: 0.567 from
  // the corner along -45 degrees on the quad untransformed. Rotated by 22.5
  // degrees it points at the green marker (-67.5 degrees; the red one marks
  // the reversed turn at -22.5), scaled by 1.5 it comes 1.5 times closer.
  const glm::vec2 rotated = arrow_centroid(f, {-1.1f, -0.55f});
  CHECK(rotated.x == doctest::Approx(-67.5f).epsilon(0.05));
  CHECK(rotated.y == doctest::Approx(0.567f).epsilon(0.05));
  const glm::vec2 scaled = arrow_centroid(f, {0.0f, -0.55f});
  CHECK(scaled.x == doctest::Approx(-45.0f).epsilon(0.05));
  CHECK(scaled.y == doctest::Approx(0.567f / 1.5f).epsilon(0.05));
  // Without the transform the arrow keeps its -45 degrees.
  for (cr::Material& m : scene.materials)
    if (m.name == "Rotation") m.base_color.transform = {};
  const glm::vec2 plain = arrow_centroid(render(scene, "texture_transform_dropped", d, 640, 480), {-1.1f, -0.55f});
  CHECK(plain.x == doctest::Approx(-45.0f).epsilon(0.05));
}

TEST_CASE("TextureTransformMultiTest: every input's TEXCOORD_0 and TEXCOORD_1 tiles match its sample tile (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/TextureTransformMultiTest/glTF/TextureTransformMultiTest.gltf");
  if (!path) return;
  cr::Scene scene = cr::load_gltf(*path);
  // One row at a time, seen head-on from far away (view directions within a
  // degree, so the tiles are lit alike) at 800 pixels per metre: the tiles,
  // 0.25 m apart, are 200 pixels apart, pixel for pixel.
  const float half_height = 0.125f, distance = 10.0f;
  const float vfov = glm::degrees(2.0f * std::atan(half_height / distance));
  // How far tile `column` (0: TEXCOORD_0, 1: TEXCOORD_1) is from the sample
  // tile: mean |luminance difference| over the inner 140x140 pixels, relative
  // to the sample's own mean deviation (its contrast), at the best alignment
  // within 6 pixels (the model's sample tiles sit 0.006 in v, 4 pixels here,
  // off the transformed ones: "virtually identical", its README says).
  auto mismatch = [&](const Frame& f, int column) {
    const int n = 140 * 140;
    double mean = 0.0, deviation = 0.0;
    for (int y = 30; y < 170; ++y)
      for (int x = 450; x < 590; ++x) mean += cr::luminance(f.at(x, y)) / n;
    for (int y = 30; y < 170; ++y)
      for (int x = 450; x < 590; ++x) deviation += std::abs(cr::luminance(f.at(x, y)) - mean) / n;
    double best = 1e30;
    for (int dy = -6; dy <= 6; ++dy)
      for (int dx = -6; dx <= 6; ++dx) {
        double diff = 0.0;
        for (int y = 30; y < 170; ++y)
          for (int x = 450; x < 590; ++x)
            diff += std::abs(cr::luminance(f.at(x - 200 * (2 - column) + dx, y + dy)) - cr::luminance(f.at(x, y))) / n;
        best = std::min(best, diff / deviation);
      }
    return best;
  };
  const struct {
    const char* input;
    float y;
  } rows[] = {{"BaseColor", 0.75f}, {"Emission", 0.5f},     {"Normal", 0.25f},
              {"MetalRough", 0.0f}, {"Occlusion", -0.25f}, {"Unlit", -0.5f}};
  for (const auto& row : rows) {
    const std::string input = row.input;
    CAPTURE(input);
    const nlohmann::json d = view(*path, {0.35f, row.y, distance}, {0.35f, row.y, 0.0f}, vfov, 5000.0f, 30000.0f);
    const Frame f = render(scene, "texture_transform_multi_" + input, d, 640, 200);
    CHECK(mismatch(f, 0) < 0.1);
    CHECK(mismatch(f, 1) < 0.1);
  }
  // The check has teeth: without their transforms the tiles differ.
  for (cr::Material& m : scene.materials)
    if (m.name == "BaseColorTest0Mat" || m.name == "BaseColorTest1Mat") m.base_color.transform = {};
  const Frame f = render(scene, "texture_transform_multi_dropped",
                         view(*path, {0.35f, 0.75f, distance}, {0.35f, 0.75f, 0.0f}, vfov, 5000.0f, 30000.0f), 640, 200);
  CHECK(mismatch(f, 0) > 0.5);
  CHECK(mismatch(f, 1) > 0.5);
}

TEST_CASE("MultiUVTest: the emissive texture reads TEXCOORD_1, showing the logo and not the failure text (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/MultiUVTest/glTF/MultiUVTest.gltf");
  if (!path) return;
  cr::Scene scene = cr::load_gltf(*path);
  // Emission alone (no sun, no sky): uv1.png through TEXCOORD_1 puts the
  // green glTF logo on the faces; read through TEXCOORD_0 it shows its white
  // "Multiple UVs not supported" lettering.
  const nlohmann::json d = {{"gltf", *path},
                            {"camera", {{"gltf_camera", 0}}},
                            {"sun", {{"azimuth_deg", 0}, {"elevation_deg", 45}, {"illuminance", 0}}},
                            {"ambient", {0, 0, 0}},
                            {"exposure_ev100", 10}};
  auto count = [](const Frame& f, float white) {
    int green = 0, lettering = 0;
    for (const glm::vec3& c : f.color) {
      green += c.g > 0.2f * white && c.g > 1.5f * c.r && c.g > 3.0f * c.b;
      lettering += std::min({c.r, c.g, c.b}) > 0.5f * white;
    }
    return glm::ivec2(green, lettering);
  };
  const float white = 1.2f * std::exp2(10.0f);
  const glm::ivec2 set1 = count(render(scene, "multi_uv", d, 480, 270), white);
  CHECK(set1.x > 500);
  CHECK(set1.y == 0);
  scene.materials.at(0).emissive.texcoord = 0;
  const glm::ivec2 set0 = count(render(scene, "multi_uv_set0", d, 480, 270), white);
  CHECK(set0.y > 100);
}

TEST_CASE("EmissiveStrengthTest: emissive 1.0 is the exposure's white, 1.2 * 2^EV100 cd/m^2, times the strength (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/EmissiveStrengthTest/glTF/EmissiveStrengthTest.gltf");
  if (!path) return;
  const cr::Scene scene = cr::load_gltf(*path);
  const glm::vec3 factor(0.1f, 0.5f, 0.9f);
  for (const float ev100 : {9.0f, 13.0f}) {
    nlohmann::json d = view(*path, {0.0f, 0.0f, 16.0f}, {0.0f, 0.0f, 0.0f}, 40.0f, 0.0f, 0.0f, ev100);
    for (const bool nits_given : {false, true}) {
      CAPTURE(ev100);
      CAPTURE(nits_given);
      if (nits_given) d["emissive_nits"] = 250.0f;
      const float white = nits_given ? 250.0f : 1.2f * std::exp2(ev100);
      const Frame f = render(scene, "emissive_strength", d, 800, 400);
      // The cubes' front faces, left to right: strengths 1, 2, 4, 8, 16.
      float strength = 1.0f, previous = 0.0f;
      for (const float x : {-6.0f, -3.0f, 0.0f, 3.0f, 6.0f}) {
        const glm::vec3 c = mean_colour(f, {x, 0.0f}, 0.3f);
        for (int k = 0; k < 3; ++k) CHECK(c[k] == doctest::Approx(factor[k] * strength * white).epsilon(1e-5));
        CHECK(cr::luminance(c) > 1.9f * previous);
        previous = cr::luminance(c);
        strength *= 2.0f;
      }
    }
  }
}

TEST_CASE("UnlitTest: every pixel of the objects is base colour * the emissive luminance, under any light (CR_ASSETS_DIR)") {
  const auto path = cr::test::asset_path("khronos/UnlitTest/glTF/UnlitTest.gltf");
  if (!path) return;
  const cr::Scene scene = cr::load_gltf(*path);
  const float white = 1.2f * std::exp2(15.0f);
  const glm::vec3 orange = glm::vec3(1.0f, 0.217637640824031f, 0.0f) * white;
  const glm::vec3 blue = glm::vec3(0.0f, 0.217637640824031f, 1.0f) * white;
  // A bright low sun and sky (white 0.25: the background stays below the objects).
  const Frame f = render(scene, "unlit", view(*path, {0.5f, 1.5f, 9.0f}, {0.0f, 0.0f, 0.0f}, 35.0f, 0.25f * white,
                                              100000.0f),
                         640, 360);
  int orange_pixels = 0, blue_pixels = 0;
  for (size_t i = 0; i < f.color.size(); ++i) {
    const glm::vec3& c = f.color[i];
    if (std::max(c.r, c.b) < 0.5f * white || f.edge[i]) continue;  // the background and the silhouettes' blends
    const glm::vec3 expected = c.r > c.b ? orange : blue;
    (c.r > c.b ? orange_pixels : blue_pixels)++;
    for (int k = 0; k < 3; ++k) CHECK(c[k] == doctest::Approx(expected[k]).epsilon(1e-6));
  }
  CHECK(orange_pixels > 2000);
  CHECK(blue_pixels > 2000);
}

TEST_CASE("point and spot lights light a floor as their closed forms say, through the renderer's batches") {
  // A 40 m white floor, lit by a point light with a 6 m range and a spot
  // pointing straight down, no sun and no sky.
  cr::test::GltfBuilder b;
  const int pos = b.floats({-20, 0, -20, -20, 0, 20, 20, 0, 20, 20, 0, -20}, "VEC3", 3);
  const int normal = b.floats({0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0}, "VEC3", 3);
  const int idx = b.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  b.add("materials", {{"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.7}}}});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", normal}}}, {"indices", idx},
                                    {"material", 0}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.doc["scenes"] = nlohmann::json::array({{{"nodes", {0}}}});
  const std::string gltf = b.write("lit_floor.gltf");
  cr::Scene scene = cr::load_gltf(gltf);
  cr::PunctualLight point;
  point.position = {-4.0f, 2.0f, 1.0f};
  point.color = {1.0f, 0.9f, 0.7f};
  point.intensity = 3000.0f;
  point.range = 6.0f;
  cr::PunctualLight spot;
  spot.type = cr::PunctualLight::Type::Spot;
  spot.position = {5.0f, 4.0f, -1.0f};
  spot.direction = {0.0f, -1.0f, 0.0f};
  spot.intensity = 8000.0f;
  spot.inner_cone_rad = 0.2f;
  spot.outer_cone_rad = 0.45f;
  scene.lights = {point, spot};
  const Frame f = render(scene, "punctual", view(gltf, {0.0f, 14.0f, 12.0f}, {0.0f, 0.0f, 0.0f}, 60.0f, 0.0f), 320, 240);

  const cr::BrdfParams floor{glm::vec3(0.8f), 0.0f, 0.7f};
  int dark = 0, lit = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::vec3 p = on_plane(f, x, y, {0.0f, 1.0f, 0.0f}, 0.0f);
      if (std::abs(p.x) > 19.0f || std::abs(p.z) > 19.0f) continue;
      const glm::vec3 v = glm::normalize(glm::vec3(f.camera.position) - p);
      glm::vec3 expected(0.0f);
      bool outside = true;
      for (const cr::PunctualLight& light : scene.lights) {
        const glm::vec3 to_light = light.position - p;
        const float d = glm::length(to_light);
        const glm::vec3 l = to_light / d;
        const cr::PunctualLightTerms t = cr::punctual_light_terms(light);
        const float window = cr::range_window(d, t.inv_range);
        const float cone = cr::cone_attenuation(glm::dot(light.direction, -l), t.cone_scale, t.cone_offset);
        outside = outside && window * cone == 0.0f;
        expected += cr::evaluate_brdf(floor, {0.0f, 1.0f, 0.0f}, v, l) * l.y * light.color * light.intensity *
                    window * cone / (d * d);
      }
      const glm::vec3& got = f.at(x, y);
      if (outside) {
        ++dark;
        CHECK(got == glm::vec3(0.0f));  // beyond the point light's range and the spot's outer cone
        continue;
      }
      ++lit;
      for (int k = 0; k < 3; ++k) CHECK(got[k] == doctest::Approx(expected[k]).epsilon(2e-3));
    }
  CHECK(dark > 10000);
  CHECK(lit > 2000);
}

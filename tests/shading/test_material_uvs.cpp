// The texture coordinates material textures read: TEXCOORD_0 or TEXCOORD_1
// per texture reference, through its KHR_texture_transform (uv' = T R S uv,
// the UV derivatives by R S so that the level of detail follows the scale),
// and the normal map's frame turned with its coordinates.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/scene/image_mips.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/texture_sampler.h"
#include "engine/shading/uv_transform.h"

using namespace cr;

namespace {

// A w x h linear image whose texel (x, y) is (x / (w - 1), y / (h - 1), 0, 1)
// in 8 bits: reading it tells where a lookup landed.
Image coordinate_image(int w, int h) {
  Image img;
  MipLevel level{w, h, {}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c : {x * 255 / (w - 1), y * 255 / (h - 1), 0, 255}) level.rgba.push_back(uint8_t(c));
  img.mips.push_back(level);
  generate_mips(img);
  return img;
}

// One RGBA8 texel, linear.
Image texel_image(uint8_t r, uint8_t g, uint8_t b) {
  Image img;
  img.mips.push_back(MipLevel{1, 1, {r, g, b, 255}});
  return img;
}

// Nearest filtering without mipmaps: a lookup returns one texel exactly.
const Sampler kNearest{Wrap::Repeat, Wrap::Repeat, Filter::Nearest, Filter::Nearest, std::nullopt};

glm::vec2 apply(const UvAffine& a, glm::vec2 uv) {
  TransformedUvs out;
  const TexturePoints p = transform_uvs(a, {1, &uv.x, &uv.y, &uv.x, &uv.y, &uv.x, &uv.y}, out);
  return {p.u[0], p.v[0]};
}

}  // namespace

TEST_CASE("uv transform: offset, rotation and scale as T * R * S, turning counter-clockwise with V down") {
  // Scale first, then the turn, then the offset.
  const UvAffine a = uv_affine({.offset = {0.25f, -0.5f}, .rotation = 0.0f, .scale = {2.0f, 3.0f}});
  const glm::vec2 scaled = apply(a, {1.0f, 1.0f});
  CHECK(scaled.x == doctest::Approx(2.25f));
  CHECK(scaled.y == doctest::Approx(2.5f));
  // A quarter turn takes +u to -v (the image's up, counter-clockwise on an
  // image whose v runs down) and +v to +u: TextureTransformTest's green marker.
  const UvAffine quarter = uv_affine({.rotation = 0.5f * kPi});
  const glm::vec2 u = apply(quarter, {1.0f, 0.0f}), v = apply(quarter, {0.0f, 1.0f});
  CHECK(u.x == doctest::Approx(0.0f).epsilon(1e-6));
  CHECK(u.y == doctest::Approx(-1.0f));
  CHECK(v.x == doctest::Approx(1.0f));
  CHECK(v.y == doctest::Approx(0.0f).epsilon(1e-6));
  // All three: S, then R, then T.
  const UvAffine both = uv_affine({.offset = {1.0f, 1.0f}, .rotation = 0.5f * kPi, .scale = {2.0f, 1.0f}});
  const glm::vec2 p = apply(both, {1.0f, 0.0f});  // S: (2, 0); R: (0, -2); T: (1, -1)
  CHECK(p.x == doctest::Approx(1.0f));
  CHECK(p.y == doctest::Approx(-1.0f));
}

TEST_CASE("uv transform: derivatives follow the linear part, so the level of detail follows the scale") {
  const UvAffine a = uv_affine({.offset = {5.0f, 7.0f}, .rotation = 0.3f, .scale = {4.0f, 4.0f}});
  float u = 0.1f, v = 0.2f, dx[2] = {1.0f / 256.0f, 0.0f}, dy[2] = {0.0f, 1.0f / 256.0f};
  TransformedUvs out;
  const TexturePoints p = transform_uvs(a, {1, &u, &v, &dx[0], &dx[1], &dy[0], &dy[1]}, out);
  // The offset moves positions only.
  CHECK(std::hypot(p.du_dx[0], p.dv_dx[0]) == doctest::Approx(4.0f / 256.0f));
  CHECK(std::hypot(p.du_dy[0], p.dv_dy[0]) == doctest::Approx(4.0f / 256.0f));
  const Image img = coordinate_image(256, 256);
  const float before = texture_lod(img, {dx[0], dx[1]}, {dy[0], dy[1]});
  const float after = texture_lod(img, {p.du_dx[0], p.dv_dx[0]}, {p.du_dy[0], p.dv_dy[0]});
  CHECK(before == doctest::Approx(0.0f).epsilon(1e-6));
  CHECK(after == doctest::Approx(2.0f));  // four times the texels per pixel: two levels down
}

TEST_CASE("material textures: each slot reads its own UV set through its own transform") {
  Scene scene;
  scene.images.push_back(coordinate_image(16, 16));
  scene.samplers.push_back(kNearest);
  const UvTransform shift{.offset = {0.25f, 0.5f}};
  Material m;
  m.base_color = {.image = 0, .sampler = 0, .texcoord = 1};                       // TEXCOORD_1
  m.metallic_roughness = {.image = 0, .sampler = 0, .transform = shift};           // TEXCOORD_0, shifted
  m.emissive = {.image = 0, .sampler = 0, .texcoord = 1, .transform = shift};      // TEXCOORD_1, shifted
  m.occlusion = {.image = 0, .sampler = 0, .texcoord = 1, .scale = 1.0f};          // shares base colour's
  m.emissive_factor = glm::vec3(1.0f);
  const MaterialTextures textures(scene, m);
  CHECK(textures.count == 4);
  CHECK(textures.channel_count == 3);
  // Lookups of one channel are adjacent (they share footprints).
  using enum MaterialTextures::Slot;
  CHECK(std::abs(textures.lookup_of[kBaseColor] - textures.lookup_of[kOcclusion]) == 1);

  SurfaceSample s;
  s.uv = {0.0f, 0.0f};
  s.uv1 = {0.5f, 0.25f};
  // Texel (x, y) of a 16x16 image covers uv [x/16, (x+1)/16): the lookups
  // land on texel (8, 4) via TEXCOORD_1, (4, 8) via TEXCOORD_0 shifted and
  // (12, 12) via TEXCOORD_1 shifted.
  auto channel = [](int texel) { return float(texel * 255 / 15) / 255.0f; };
  const MaterialSample ms = evaluate_material(scene, m, s, 1.0f);
  CHECK(ms.base_color.r == doctest::Approx(channel(8)));
  CHECK(ms.base_color.g == doctest::Approx(channel(4)));
  CHECK(ms.occlusion == doctest::Approx(channel(8)));
  CHECK(ms.roughness == doctest::Approx(channel(8)));  // G of texel (4, 8)
  CHECK(ms.emissive.r == doctest::Approx(channel(12)));
  CHECK(ms.emissive.g == doctest::Approx(channel(12)));
  // sample_material_texture (alpha coverage's lookup) reads the same place.
  CHECK(sample_material_texture(scene, m.emissive, s).r == doctest::Approx(channel(12)));
  CHECK(sample_material_texture(scene, m.base_color, s).g == doctest::Approx(channel(4)));
  CHECK(needs_uv1(m));
  Material uv0_only;
  uv0_only.base_color = {.image = 0, .transform = shift};
  CHECK_FALSE(needs_uv1(uv0_only));
}

TEST_CASE("material textures: untransformed slots on one UV set are one channel, in slot order") {
  Scene scene;
  scene.images.push_back(coordinate_image(4, 4));
  Material m;
  m.base_color = {.image = 0};
  m.metallic_roughness = {.image = 0};
  m.normal = {.image = 0};
  m.occlusion = {.image = 0};
  m.emissive = {.image = 0};  // emissive factor 0: not read
  const MaterialTextures textures(scene, m);
  REQUIRE(textures.channel_count == 1);
  CHECK_FALSE(textures.channels[0].transformed);
  CHECK(textures.count == 4);
  for (int slot = 0; slot < 4; ++slot) CHECK(textures.lookup_of[slot] == slot);
  CHECK(textures.lookup_of[MaterialTextures::kEmissive] == -1);
  CHECK_FALSE(textures.normal_turned);
}

TEST_CASE("normal maps read through a transform tilt towards the transformed coordinates") {
  // A surface in the XZ plane facing +Y with u along +X and v along +Z: the
  // tangent is +X and the bitangent cross(N, T) = -Z, towards decreasing v.
  Scene scene;
  scene.images.push_back(texel_image(255, 128, 128));  // tilted fully towards the map's +u
  scene.images.push_back(texel_image(128, 255, 128));  // ... towards its bitangent (decreasing v)
  SurfaceSample s;
  s.normal = {0.0f, 1.0f, 0.0f};
  s.tangent = {1.0f, 0.0f, 0.0f, 1.0f};
  for (const float rotation : {0.0f, 0.4f, 2.5f}) {
    for (const float mirror : {1.0f, -1.0f}) {
      CAPTURE(rotation);
      CAPTURE(mirror);
      const UvTransform t{.offset = {0.3f, 0.1f}, .rotation = rotation, .scale = {3.0f * mirror, 3.0f}};
      const UvAffine a = uv_affine(t);
      // On the surface u' = m00 x + m01 z and v' = m10 x + m11 z: the map's
      // +u' points along (m00, m01), its bitangent along -(m10, m11).
      const glm::vec3 along_u = glm::normalize(glm::vec3(a.m00, 0.0f, a.m01));
      const glm::vec3 along_b = -glm::normalize(glm::vec3(a.m10, 0.0f, a.m11));
      Material m;
      m.normal = {.image = 0, .scale = 1.0f, .transform = t};
      const glm::vec3 n = evaluate_material(scene, m, s, 1.0f).normal;
      CHECK(glm::dot(n, along_u) > 0.999f);
      m.normal.image = 1;
      CHECK(glm::dot(evaluate_material(scene, m, s, 1.0f).normal, along_b) > 0.999f);
    }
  }
}

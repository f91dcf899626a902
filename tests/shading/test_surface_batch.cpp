#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/half_rounding.h"
#include "engine/raster/triangle_interp.h"
#include "engine/scene/image_mips.h"
#include "engine/shading/material_batch.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/sh_lighting.h"
#include "engine/shading/shade_surface.h"
#include "engine/shading/surface.h"
#include "engine/shading/surface_batch.h"

using namespace cr;

namespace {

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// Deterministic pseudo-random floats in [lo, hi).
struct Lcg {
  uint32_t state = 12345;
  float next(float lo, float hi) {
    state = state * 1664525u + 1013904223u;
    return lo + (hi - lo) * float(state >> 8) * (1.0f / 16777216.0f);
  }
  glm::vec3 vec3(float lo, float hi) { return {next(lo, hi), next(lo, hi), next(lo, hi)}; }
};

// Four triangles of random attributes; triangle 1 has a zero normal at every
// vertex (the geometric fallback), triangle 2 tangents along its normals
// (the orthogonal_tangent fallback).
Primitive random_primitive(Lcg& rng, bool normals, bool tangents, bool uv, bool color, bool uv1) {
  Primitive p;
  for (int v = 0; v < 12; ++v) {
    p.positions.push_back(rng.vec3(-5.0f, 5.0f));
    const glm::vec3 n = v / 3 == 1 ? glm::vec3(0.0f) : rng.vec3(-1.0f, 1.0f);
    if (normals) p.normals.push_back(n);
    if (tangents) p.tangents.push_back(v / 3 == 2 ? glm::vec4(n, 1.0f) : glm::vec4(rng.vec3(-1.0f, 1.0f), v % 2 ? 1.0f : -1.0f));
    if (uv) p.texcoords.push_back({rng.next(-3.0f, 3.0f), rng.next(-3.0f, 3.0f)});
    if (uv1) p.texcoords1.push_back({rng.next(-2.0f, 2.0f), rng.next(-2.0f, 2.0f)});
    if (color) p.colors.push_back({rng.vec3(0.0f, 1.0f), rng.next(0.0f, 1.0f)});
    p.indices.push_back(uint32_t(v));
  }
  return p;
}

Draw random_draw(Lcg& rng, bool mirrored) {
  glm::mat4 world = glm::rotate(glm::mat4(1.0f), rng.next(0.0f, 6.0f), glm::normalize(rng.vec3(0.1f, 1.0f)));
  world = glm::scale(glm::translate(world, rng.vec3(-100.0f, 100.0f)), glm::vec3(mirrored ? -1.5f : 1.5f, 0.7f, 2.0f));
  Draw d;
  d.world = world;
  d.normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
  d.mirrored = mirrored;
  return d;
}

TriangleInterp random_planes(Lcg& rng) {
  TriangleInterp t{};
  for (int i = 0; i < 3; ++i) {
    t.u0[i] = rng.next(0.05f, 1.0f);
    t.ux[i] = rng.next(-0.01f, 0.01f);
    t.uy[i] = rng.next(-0.01f, 0.01f);
  }
  t.ref_x = 300.5f;
  t.ref_y = 200.5f;
  return t;
}

void check_point(const SurfaceBatch& b, int k, const SurfaceSample& s, bool with_tangent, bool with_uv1) {
  CHECK(same_bits(b.px[k], s.position.x));
  CHECK(same_bits(b.py[k], s.position.y));
  CHECK(same_bits(b.pz[k], s.position.z));
  CHECK(same_bits(b.nx[k], s.normal.x));
  CHECK(same_bits(b.ny[k], s.normal.y));
  CHECK(same_bits(b.nz[k], s.normal.z));
  if (with_tangent) {
    CHECK(same_bits(b.tx[k], s.tangent.x));
    CHECK(same_bits(b.ty[k], s.tangent.y));
    CHECK(same_bits(b.tz[k], s.tangent.z));
    CHECK(same_bits(b.tw[k], s.tangent.w));
  }
  CHECK(same_bits(b.u[k], s.uv.x));
  CHECK(same_bits(b.v[k], s.uv.y));
  CHECK(same_bits(b.du_dx[k], s.duv_dx.x));
  CHECK(same_bits(b.dv_dx[k], s.duv_dx.y));
  CHECK(same_bits(b.du_dy[k], s.duv_dy.x));
  CHECK(same_bits(b.dv_dy[k], s.duv_dy.y));
  if (with_uv1) {
    CHECK(same_bits(b.u1[k], s.uv1.x));
    CHECK(same_bits(b.v1[k], s.uv1.y));
    CHECK(same_bits(b.du1_dx[k], s.duv1_dx.x));
    CHECK(same_bits(b.dv1_dx[k], s.duv1_dx.y));
    CHECK(same_bits(b.du1_dy[k], s.duv1_dy.x));
    CHECK(same_bits(b.dv1_dy[k], s.duv1_dy.y));
  }
  CHECK(same_bits(b.cr[k], s.color.r));
  CHECK(same_bits(b.cg[k], s.color.g));
  CHECK(same_bits(b.cb[k], s.color.b));
  CHECK(same_bits(b.ca[k], s.color.a));
}

}  // namespace

TEST_CASE("surface batch: spans added and finished hold at()'s floats bit for bit") {
  Lcg rng;
  for (int streams = 0; streams < 32; ++streams) {
    const Primitive p = random_primitive(rng, streams & 1, streams & 2, streams & 4, streams & 8, streams & 16);
    for (const bool mirrored : {false, true}) {
      const Draw d = random_draw(rng, mirrored);
      // Spans of several triangles, facings, tangent and TEXCOORD_1 needs
      // share one batch, the last one filling it.
      SurfaceBatch batch;
      struct Span {
        TriangleSurface surface;
        TriangleInterp planes;
        int x0, count, y;
        bool with_tangent, with_uv1;
      };
      std::vector<Span> spans;
      int added = 0;
      for (int s = 0; added < SurfaceBatch::kCapacity; ++s) {
        const bool front = s % 2 == 0, with_tangent = s % 3 != 1, with_uv1 = s % 5 < 3;
        const bool half = (s + streams) % 3 == 0;  // the mobile profile's fp16 varyings, in the same batch
        const int count = std::min(1 + 7 * (s % 4), SurfaceBatch::kCapacity - added);
        spans.push_back({TriangleSurface(p, d, uint32_t(s % 4), front, with_tangent, with_uv1, half), random_planes(rng),
                         290 + 3 * s, count, 190 + s, with_tangent, with_uv1});
        const Span& span = spans.back();
        span.surface.add_span(batch, span.planes, span.x0, span.count, span.y);
        added += count;
      }
      REQUIRE(batch.full());
      batch.finish();
      int k = 0;
      for (const Span& span : spans)
        for (int j = 0; j < span.count; ++j, ++k) {
          const Barycentrics bary = interpolate(span.planes, float(span.x0 + j) + 0.5f, float(span.y) + 0.5f);
          check_point(batch, k, span.surface.at(bary), span.with_tangent, span.with_uv1);
        }
    }
  }
}

namespace {

// Two 16x16 random images (one with decoded floats, one left as RGBA8: the
// table path), a sampler other than the common one, and materials that take
// every path of the material evaluation: factors only, textures on both UV
// sets through their own transforms (some slots sharing one), normal maps
// (turned by a transform, mirrored), emission with a strength, unlit.
struct MaterialScene {
  Scene scene;
  std::vector<Material> materials;
};

MaterialScene material_scene(Lcg& rng) {
  MaterialScene out;
  Scene& scene = out.scene;
  for (const bool srgb : {true, false}) {
    Image image;
    image.srgb = srgb;
    MipLevel level{16, 16, {}};
    for (int i = 0; i < 16 * 16 * 4; ++i) level.rgba.push_back(uint8_t(rng.next(0.0f, 256.0f)));
    image.mips.push_back(level);
    generate_mips(image);
    scene.images.push_back(image);
  }
  scene.samplers.push_back({Wrap::MirroredRepeat, Wrap::ClampToEdge, Filter::Nearest, Filter::Linear, Filter::Linear});
  const UvTransform shifted{.offset = {0.3f, -0.2f}, .rotation = 0.7f, .scale = {1.5f, 0.5f}};
  const UvTransform mirrored{.rotation = -2.0f, .scale = {-1.0f, 2.0f}};
  std::vector<Material>& m = out.materials;
  m.resize(7);
  m[0].base_color_factor = {0.8f, 0.6f, 0.4f, 1.0f};  // factors only
  m[1].base_color = {.image = 0};                     // textures, normal map, occlusion
  m[1].metallic_roughness = {.image = 1, .sampler = 0};
  m[1].normal = {.image = 1, .scale = 0.8f};
  m[1].occlusion = {.image = 0, .sampler = 0, .scale = 0.5f};
  m[2] = m[1];  // blended, emissive, strong normal map
  m[2].alpha_mode = AlphaMode::Blend;
  m[2].emissive_factor = {1.0f, 0.5f, 0.25f};
  m[2].emissive = {.image = 0};
  m[2].normal.scale = 40.0f;
  m[3].normal = {.image = 0, .scale = 1.0f};  // normal map only
  // Both UV sets: base colour and occlusion share set 1 and a transform, the
  // metal-rough map has that transform on set 0, the normal map its own
  // (mirroring) on set 1, the emission set 0 untransformed.
  m[4].base_color = {.image = 0, .texcoord = 1, .transform = shifted};
  m[4].metallic_roughness = {.image = 0, .transform = shifted};
  m[4].normal = {.image = 1, .texcoord = 1, .scale = 1.2f, .transform = mirrored};
  m[4].occlusion = {.image = 0, .texcoord = 1, .scale = 0.7f, .transform = shifted};
  m[4].emissive = {.image = 1, .sampler = 0};
  m[4].emissive_factor = {0.5f, 1.0f, 0.2f};
  m[4].emissive_strength = 3.0f;
  // Unlit: the base colour alone (its normal map and emission ignored), blended.
  m[5].unlit = true;
  m[5].alpha_mode = AlphaMode::Blend;
  m[5].base_color = {.image = 0, .texcoord = 1, .transform = mirrored};
  m[5].normal = {.image = 1};
  m[5].emissive_factor = glm::vec3(1.0f);
  m[6].unlit = true;  // unlit, factors only
  m[6].base_color_factor = {0.2f, 0.9f, 0.5f, 0.6f};
  return out;
}

// A full batch of points on random triangles (runs of one to three points
// sharing a material, so that its textures are looked up run by run), and
// each point's surface as at() gives it.
struct BatchPoints {
  SurfaceBatch surfaces;
  const Material* of[SurfaceBatch::kCapacity];
  std::vector<SurfaceSample> samples;
};

void fill_batch(Lcg& rng, const Primitive& p, const Draw& d, const std::vector<Material>& materials,
                BatchPoints& out) {
  while (!out.surfaces.full()) {
    const int k = out.surfaces.count;
    const Material& m = materials[size_t((k / 3 + k / 7) % materials.size())];
    const TriangleSurface triangle(p, d, uint32_t(k % 4), k % 3 != 0, needs_tangent(m), needs_uv1(m));
    const TriangleInterp planes = random_planes(rng);
    triangle.add_span(out.surfaces, planes, 300 + k, 1, 200);
    out.of[k] = &m;
    out.samples.push_back(triangle.at(interpolate(planes, float(300 + k) + 0.5f, 200.5f)));
  }
  out.surfaces.finish();
}

}  // namespace

TEST_CASE("material batch: evaluate_materials appends SurfaceShader::add's floats bit for bit") {
  Lcg rng;
  const MaterialScene ms = material_scene(rng);
  const Primitive p = random_primitive(rng, true, true, true, true, true);
  const Draw d = random_draw(rng, false);
  LightEnvironment light;
  const float luminance = 1234.5f;
  const SurfaceShader shader({.scene = &ms.scene, .light = &light, .emissive_luminance = luminance});
  BatchPoints points;
  fill_batch(rng, p, d, ms.materials, points);
  ShadingBatch batch;
  evaluate_materials(ms.scene, points.surfaces, points.of, luminance, batch);
  ShadingBatch expected;
  for (int k = 0; k < SurfaceBatch::kCapacity; ++k) shader.add(expected, *points.of[k], points.samples[size_t(k)]);
  REQUIRE(batch.count == expected.count);
  REQUIRE(batch.any_unlit);
  REQUIRE(expected.any_unlit);
  for (int k = 0; k < batch.count; ++k) {
    CAPTURE(k);
    for (int c = 0; c < 3; ++c) CHECK(same_bits(batch.position[k][c], expected.position[k][c]));
    const float* fields[][2] = {{batch.gx, expected.gx},       {batch.gy, expected.gy},
                                {batch.gz, expected.gz},       {batch.nx, expected.nx},
                                {batch.ny, expected.ny},       {batch.nz, expected.nz},
                                {batch.base_r, expected.base_r}, {batch.base_g, expected.base_g},
                                {batch.base_b, expected.base_b}, {batch.metallic, expected.metallic},
                                {batch.roughness, expected.roughness}, {batch.occlusion, expected.occlusion},
                                {batch.emissive_r, expected.emissive_r}, {batch.emissive_g, expected.emissive_g},
                                {batch.emissive_b, expected.emissive_b}, {batch.alpha, expected.alpha},
                                {batch.unlit, expected.unlit}};
    for (const auto& f : fields) CHECK(same_bits(f[0][k], f[1][k]));
  }
}

TEST_CASE("shading batch: sun, shadow, point and spot lights and unlit points give shade()'s radiance bit for bit") {
  Lcg rng;
  MaterialScene ms = material_scene(rng);
  PunctualLight point;
  point.position = {5.0f, 40.0f, -10.0f};
  point.color = {1.0f, 0.8f, 0.6f};
  point.intensity = 4e6f;
  PunctualLight spot;
  spot.type = PunctualLight::Type::Spot;
  spot.position = {-20.0f, 60.0f, 30.0f};
  spot.direction = glm::normalize(glm::vec3(0.2f, -1.0f, -0.3f));
  spot.intensity = 9e6f;
  spot.range = 150.0f;
  spot.inner_cone_rad = 0.3f;
  spot.outer_cone_rad = 0.9f;
  ms.scene.lights = {point, spot};
  const Primitive p = random_primitive(rng, true, true, true, true, true);
  const Draw d = random_draw(rng, true);
  LightEnvironment light;
  light.sun_direction = glm::normalize(glm::vec3(0.3f, 0.8f, -0.2f));
  light.sun_illuminance = glm::vec3(9e4f, 8e4f, 7e4f);
  light.ambient_sh = sh_constant_radiance(glm::vec3(2000.0f, 2500.0f, 3000.0f));
  light.ambient_sh[2] = glm::vec3(400.0f, 300.0f, -100.0f);
  ShadowMap shadow = fit_shadow_map(Camera::look_at({0, 2, 5}, {0, 0, 0}, 1.0f, 1.0f, 0.1f), light.sun_direction,
                                    300.0f, 64, 1, glm::vec3(-150.0f), glm::vec3(150.0f));
  for (size_t i = 0; i < shadow.depth.size(); ++i) shadow.depth[i] = (i % 64) < 32 ? 1.0f : 0.0f;
  const ShadingInputs in{.scene = &ms.scene, .light = &light, .shadow = &shadow,
                         .camera_position = glm::dvec3(10.0, 80.0, 40.0), .emissive_luminance = 5000.0f};
  const SurfaceShader shader(in);
  BatchPoints points;
  fill_batch(rng, p, d, ms.materials, points);
  ShadingBatch batch;
  evaluate_materials(ms.scene, points.surfaces, points.of, in.emissive_luminance, batch);
  shader.shade_batch(batch);
  for (int k = 0; k < batch.count; ++k) {
    CAPTURE(k);
    const glm::vec4 expected = shader.shade(*points.of[k], points.samples[size_t(k)]);
    for (int c = 0; c < 3; ++c) CHECK(same_bits(batch.radiance(k)[c], expected[c]));
    // Unlit points: base colour * the emissive luminance, nothing else.
    if (points.of[k]->unlit) CHECK(same_bits(batch.out_r[k], batch.base_r[k] * in.emissive_luminance));
  }
}

TEST_CASE("surface: fp16 varyings round the interpolated UVs, normal and colour to halves, within half a half-ulp") {
  Lcg rng;
  const Primitive p = random_primitive(rng, true, true, true, true, false);
  const Draw d = random_draw(rng, false);
  const TriangleSurface full(p, d, 0, true, true, false, false), half(p, d, 0, true, true, false, true);
  for (int k = 0; k < 50; ++k) {
    const Barycentrics bary = interpolate(random_planes(rng), 300.5f + float(k), 200.5f);
    const SurfaceSample a = full.at(bary), b = half.at(bary);
    for (int c = 0; c < 2; ++c) {
      CHECK(round_to_half(b.uv[c]) == b.uv[c]);
      // Half of fp16's spacing at |uv|: 2^(floor(log2|uv|) - 11), at least half the smallest denormal.
      const float spacing = std::max(std::exp2(std::floor(std::log2(std::abs(a.uv[c]))) - 10.0f), 0x1p-24f);
      CHECK(std::abs(a.uv[c] - b.uv[c]) <= 0.5f * spacing);
    }
    for (int c = 0; c < 4; ++c) CHECK(round_to_half(b.color[c]) == b.color[c]);
    CHECK(b.position == a.position);  // positions stay float
    CHECK(b.duv_dx == a.duv_dx);      // and so do the UV derivatives
  }
}

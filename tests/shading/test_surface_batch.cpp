#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/raster/triangle_interp.h"
#include "engine/scene/image_mips.h"
#include "engine/scene/image_texels.h"
#include "engine/shading/material_batch.h"
#include "engine/shading/material_eval.h"
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
Primitive random_primitive(Lcg& rng, bool normals, bool tangents, bool uv, bool color) {
  Primitive p;
  for (int v = 0; v < 12; ++v) {
    p.positions.push_back(rng.vec3(-5.0f, 5.0f));
    const glm::vec3 n = v / 3 == 1 ? glm::vec3(0.0f) : rng.vec3(-1.0f, 1.0f);
    if (normals) p.normals.push_back(n);
    if (tangents) p.tangents.push_back(v / 3 == 2 ? glm::vec4(n, 1.0f) : glm::vec4(rng.vec3(-1.0f, 1.0f), v % 2 ? 1.0f : -1.0f));
    if (uv) p.texcoords.push_back({rng.next(-3.0f, 3.0f), rng.next(-3.0f, 3.0f)});
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

void check_point(const SurfaceBatch& b, int k, const SurfaceSample& s, bool with_tangent) {
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
  CHECK(same_bits(b.cr[k], s.color.r));
  CHECK(same_bits(b.cg[k], s.color.g));
  CHECK(same_bits(b.cb[k], s.color.b));
  CHECK(same_bits(b.ca[k], s.color.a));
}

}  // namespace

TEST_CASE("surface batch: spans added and finished hold at()'s floats bit for bit") {
  Lcg rng;
  for (int streams = 0; streams < 16; ++streams) {
    const Primitive p = random_primitive(rng, streams & 1, streams & 2, streams & 4, streams & 8);
    for (const bool mirrored : {false, true}) {
      const Draw d = random_draw(rng, mirrored);
      // Spans of several triangles, facings and tangent needs share one batch,
      // the last one filling it.
      SurfaceBatch batch;
      struct Span {
        TriangleSurface surface;
        TriangleInterp planes;
        int x0, count, y;
        bool with_tangent;
      };
      std::vector<Span> spans;
      int added = 0;
      for (int s = 0; added < SurfaceBatch::kCapacity; ++s) {
        const bool front = s % 2 == 0, with_tangent = s % 3 != 1;
        const int count = std::min(1 + 7 * (s % 4), SurfaceBatch::kCapacity - added);
        spans.push_back({TriangleSurface(p, d, uint32_t(s % 4), front, with_tangent), random_planes(rng),
                         290 + 3 * s, count, 190 + s, with_tangent});
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
          check_point(batch, k, span.surface.at(bary), span.with_tangent);
        }
    }
  }
}

TEST_CASE("material batch: evaluate_materials appends SurfaceShader::add's floats bit for bit") {
  Lcg rng;
  Scene scene;
  // A 16x16 RGBA8 chain (mips and decoded floats) of random texels, and one
  // left as RGBA8 only (the table path).
  for (const bool srgb : {true, false}) {
    Image image;
    image.srgb = srgb;
    MipLevel level{16, 16, {}, {}};
    for (int i = 0; i < 16 * 16 * 4; ++i) level.rgba.push_back(uint8_t(rng.next(0.0f, 256.0f)));
    image.mips.push_back(level);
    generate_mips(image);
    if (srgb) decode_texels(image);
    scene.images.push_back(image);
  }
  scene.samplers.push_back({Wrap::MirroredRepeat, Wrap::ClampToEdge, Filter::Nearest, Filter::Linear, Filter::Linear});
  std::vector<Material> materials(4);
  materials[0].base_color_factor = {0.8f, 0.6f, 0.4f, 1.0f};  // factors only
  materials[1].base_color = {0, -1};                          // textures, normal map, occlusion
  materials[1].metallic_roughness = {1, 0};
  materials[1].normal = {1, -1, 0, 0.8f};
  materials[1].occlusion = {0, 0, 0, 0.5f};
  materials[2] = materials[1];                                // blended, emissive, strong normal map
  materials[2].alpha_mode = AlphaMode::Blend;
  materials[2].emissive_factor = {1.0f, 0.5f, 0.25f};
  materials[2].emissive = {0, -1};
  materials[2].normal.scale = 40.0f;
  materials[3].normal = {0, -1, 0, 1.0f};                     // normal map only

  const Primitive p = random_primitive(rng, true, true, true, true);
  const Draw d = random_draw(rng, false);
  LightEnvironment light;
  const SurfaceShader shader({&scene, &light, nullptr, glm::dvec3(0.0)});
  SurfaceBatch surfaces;
  const Material* of[SurfaceBatch::kCapacity];
  std::vector<SurfaceSample> samples;
  while (!surfaces.full()) {
    const int k = surfaces.count;
    // Runs of one to three points share a material: its textures are looked up run by run.
    const Material& m = materials[size_t((k / 3 + k / 7) % 4)];
    const TriangleSurface triangle(p, d, uint32_t(k % 4), k % 3 != 0, needs_tangent(m));
    const TriangleInterp planes = random_planes(rng);
    triangle.add_span(surfaces, planes, 300 + k, 1, 200);
    of[k] = &m;
    samples.push_back(triangle.at(interpolate(planes, float(300 + k) + 0.5f, 200.5f)));
  }
  surfaces.finish();
  ShadingBatch batch;
  evaluate_materials(scene, surfaces, of, batch);
  ShadingBatch expected;
  for (int k = 0; k < SurfaceBatch::kCapacity; ++k) shader.add(expected, *of[k], samples[size_t(k)]);
  REQUIRE(batch.count == expected.count);
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
                                {batch.emissive_b, expected.emissive_b}, {batch.alpha, expected.alpha}};
    for (const auto& f : fields) CHECK(same_bits(f[0][k], f[1][k]));
  }
}

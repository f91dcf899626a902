#include "engine/shading/material_batch.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/brdf.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/safe_normalize.h"
#include "engine/shading/texture_sampler.h"

namespace cr {
namespace {

static_assert(SurfaceBatch::kCapacity == ShadingBatch::kCapacity);
static_assert(SurfaceBatch::kCapacity == TexturePoints::kCapacity);

// Normal-map normals in tangent space (XY scaled); `mapped` is 1 where the
// point's material has a normal map, else 0.
struct TangentNormals {
  float x[ShadingBatch::kCapacity], y[ShadingBatch::kCapacity], z[ShadingBatch::kCapacity];
  float mapped[ShadingBatch::kCapacity];
};

// material_eval.cpp's apply_normal_map per lane: B = cross(N, T) * w,
// normalize_or((T x + B y) + N z, N); the shading normal stays N where
// unmapped. Out of line so that it stays a vectorised loop (restrict: the
// batches are distinct).
[[gnu::noinline]] void apply_normal_maps(const SurfaceBatch& __restrict s, const TangentNormals& __restrict t,
                                         ShadingBatch& __restrict b) {
  for (int i = 0; i < s.count; ++i) {
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float tx = s.tx[i], ty = s.ty[i], tz = s.tz[i], w = s.tw[i];
    const float mx = t.x[i], my = t.y[i], mz = t.z[i], mapped = t.mapped[i];
    const float bx = (ny * tz - ty * nz) * w;
    const float by = (nz * tx - tz * nx) * w;
    const float bz = (nx * ty - tx * ny) * w;
    const float x = tx * mx + bx * my + nx * mz;
    const float y = ty * mx + by * my + ny * mz;
    const float z = tz * mx + bz * my + nz * mz;
    const float len = std::sqrt(x * x + y * y + z * z);
    // Two selects: with `&&` the loop had control flow and ran scalar.
    const bool ok = usable_length(len);
    const float mapped_x = ok ? x / len : nx, mapped_y = ok ? y / len : ny, mapped_z = ok ? z / len : nz;
    b.nx[i] = mapped != 0.0f ? mapped_x : nx;
    b.ny[i] = mapped != 0.0f ? mapped_y : ny;
    b.nz[i] = mapped != 0.0f ? mapped_z : nz;
  }
}

// evaluate_material_factors over the points [begin, end) of one material,
// lookup k's texel of point i at texels[k * n + i - begin]: field by field,
// each a loop that vectorises (restrict: the batches and texels are
// distinct; a slot without a texture reads 1, and factor * 1 is the factor,
// so such loops drop the texel). The same floats as point by point.
[[gnu::noinline]] void run_factors(const Material& material, const MaterialTextures& textures,
                                   const glm::vec4* __restrict texels, int begin, int end, float emissive_luminance,
                                   const SurfaceBatch& __restrict s, TangentNormals& __restrict t,
                                   ShadingBatch& __restrict b) {
  using enum MaterialTextures::Slot;
  const int n = end - begin;
  auto slot = [&](MaterialTextures::Slot k) -> const glm::vec4* {
    return textures.lookup_of[k] >= 0 ? texels + textures.lookup_of[k] * n - begin : nullptr;
  };
  auto saturate = [](float x) { return clamp_nan_safe(x, 0.0f, 1.0f); };

  const glm::vec4 f = material.base_color_factor;
  const bool blend = material.alpha_mode == AlphaMode::Blend;
  if (const glm::vec4* tex = slot(kBaseColor)) {
    for (int i = begin; i < end; ++i) {
      const float r = f.r * tex[i].r * s.cr[i], g = f.g * tex[i].g * s.cg[i], bl = f.b * tex[i].b * s.cb[i];
      b.base_r[i] = std::max(r, 0.0f);
      b.base_g[i] = std::max(g, 0.0f);
      b.base_b[i] = std::max(bl, 0.0f);
      b.alpha[i] = blend ? saturate(f.a * tex[i].a * s.ca[i]) : 1.0f;
    }
  } else {
    for (int i = begin; i < end; ++i) {
      b.base_r[i] = std::max(f.r * s.cr[i], 0.0f);
      b.base_g[i] = std::max(f.g * s.cg[i], 0.0f);
      b.base_b[i] = std::max(f.b * s.cb[i], 0.0f);
      b.alpha[i] = blend ? saturate(f.a * s.ca[i]) : 1.0f;
    }
  }

  if (material.unlit) {
    // The base colour is the radiance; the other fields at MaterialSample's defaults.
    for (int i = begin; i < end; ++i) {
      b.metallic[i] = b.roughness[i] = b.occlusion[i] = 1.0f;
      t.x[i] = t.y[i] = t.z[i] = t.mapped[i] = 0.0f;
      b.emissive_r[i] = b.base_r[i] * emissive_luminance;
      b.emissive_g[i] = b.base_g[i] * emissive_luminance;
      b.emissive_b[i] = b.base_b[i] * emissive_luminance;
    }
    return;
  }

  const float roughness = material.roughness_factor, metallic = material.metallic_factor;
  if (const glm::vec4* tex = slot(kMetallicRoughness)) {
    for (int i = begin; i < end; ++i) {
      b.roughness[i] = saturate(roughness * tex[i].g);
      b.metallic[i] = saturate(metallic * tex[i].b);
    }
  } else {
    for (int i = begin; i < end; ++i) {
      b.roughness[i] = saturate(roughness);
      b.metallic[i] = saturate(metallic);
    }
  }

  // A slot has a texture exactly where the material's reference is valid.
  // glTF: RGB in [0,1] -> [-1,1], XY scaled by normalTexture.scale.
  if (const glm::vec4* normal = slot(kNormal)) {
    const float scale = material.normal.scale;
    for (int i = begin; i < end; ++i) {
      t.x[i] = (normal[i].x * 2.0f - 1.0f) * scale;
      t.y[i] = (normal[i].y * 2.0f - 1.0f) * scale;
      t.z[i] = normal[i].z * 2.0f - 1.0f;
      t.mapped[i] = 1.0f;
    }
    if (textures.normal_turned) {
      const NormalMapTurn turn = textures.normal_turn;
      for (int i = begin; i < end; ++i) {
        const float x = t.x[i], y = t.y[i];
        t.x[i] = turned_x(turn, x, y);
        t.y[i] = turned_y(turn, x, y);
      }
    }
  } else {
    for (int i = begin; i < end; ++i) t.x[i] = t.y[i] = t.z[i] = t.mapped[i] = 0.0f;
  }

  const glm::vec4* occlusion = slot(kOcclusion);
  const float strength = saturate(material.occlusion.scale);
  for (int i = begin; i < end; ++i) b.occlusion[i] = occlusion ? 1.0f + strength * (occlusion[i].r - 1.0f) : 1.0f;

  const bool emitting = emits(material);
  const glm::vec3 e = emissive_scale(material, emissive_luminance);
  const glm::vec4* emissive = slot(kEmissive);
  for (int i = begin; i < end; ++i) {
    const glm::vec4 texel = emissive ? emissive[i] : glm::vec4(1.0f);
    b.emissive_r[i] = emitting ? e.r * texel.r : 0.0f;
    b.emissive_g[i] = emitting ? e.g * texel.g : 0.0f;
    b.emissive_b[i] = emitting ? e.b * texel.b : 0.0f;
  }
}

}  // namespace

void evaluate_materials(const Scene& scene, const SurfaceBatch& surfaces, const Material* const* materials,
                        float emissive_luminance, ShadingBatch& batch) {
  TangentNormals normals;
  bool any_mapped = false;
  batch.count = surfaces.count;
  batch.any_unlit = false;
  for (int i = 0; i < surfaces.count; ++i) {
    batch.position[i] = {surfaces.px[i], surfaces.py[i], surfaces.pz[i]};
    batch.gx[i] = batch.nx[i] = surfaces.nx[i];
    batch.gy[i] = batch.ny[i] = surfaces.ny[i];
    batch.gz[i] = batch.nz[i] = surfaces.nz[i];
  }
  // Runs of points share a material: its textures are set up once a run,
  // looked up for the whole run together, and its factors applied run-wide.
  glm::vec4 texels[MaterialTextures::kSlots * ShadingBatch::kCapacity];
  for (int begin = 0, end = 0; begin < surfaces.count; begin = end) {
    const Material& material = *materials[begin];
    end = begin + 1;
    while (end < surfaces.count && materials[end] == &material) ++end;
    const MaterialTextures textures(scene, material);
    const int n = end - begin;
    const TexturePoints uv[2] = {
        {n, surfaces.u + begin, surfaces.v + begin, surfaces.du_dx + begin, surfaces.dv_dx + begin,
         surfaces.du_dy + begin, surfaces.dv_dy + begin},
        {n, surfaces.u1 + begin, surfaces.v1 + begin, surfaces.du1_dx + begin, surfaces.dv1_dx + begin,
         surfaces.du1_dy + begin, surfaces.dv1_dy + begin}};
    sample_material_textures(textures, uv, texels);
    run_factors(material, textures, texels, begin, end, emissive_luminance, surfaces, normals, batch);
    any_mapped |= needs_tangent(material);
    if (material.unlit) {
      // Every other point of the batch is lit: marked so at the first unlit run.
      if (!batch.any_unlit) std::fill(batch.unlit, batch.unlit + surfaces.count, 0.0f);
      batch.any_unlit = true;
      std::fill(batch.unlit + begin, batch.unlit + end, 1.0f);
    }
  }
  if (any_mapped) apply_normal_maps(surfaces, normals, batch);
}

}  // namespace cr

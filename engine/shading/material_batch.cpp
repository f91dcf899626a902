#include "engine/shading/material_batch.h"

#include <cmath>

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

}  // namespace

void evaluate_materials(const Scene& scene, const SurfaceBatch& surfaces, const Material* const* materials,
                        ShadingBatch& batch) {
  TangentNormals normals;
  bool any_mapped = false;
  batch.count = surfaces.count;
  // Runs of points share a material: its textures are set up once a run and
  // looked up for the whole run together.
  MaterialTextures textures;
  glm::vec4 texels[MaterialTextures::kSlots * ShadingBatch::kCapacity];
  int run_begin = 0, run_end = 0;
  for (int i = 0; i < surfaces.count; ++i) {
    const Material& material = *materials[i];
    if (i == run_end) {
      run_begin = i;
      run_end = i + 1;
      while (run_end < surfaces.count && materials[run_end] == &material) ++run_end;
      textures = MaterialTextures(scene, material);
      const TexturePoints points{run_end - run_begin,  surfaces.u + i,     surfaces.v + i,    surfaces.du_dx + i,
                                 surfaces.dv_dx + i, surfaces.du_dy + i, surfaces.dv_dy + i};
      sample_textures(textures.lookups, textures.count, points, texels);
    }
    MaterialSample m;
    glm::vec3 tangent_normal(0.0f);
    evaluate_material_factors(material, textures, texels + (i - run_begin), run_end - run_begin,
                              {surfaces.cr[i], surfaces.cg[i], surfaces.cb[i], surfaces.ca[i]}, m, tangent_normal);
    const bool mapped = material.normal.valid();
    any_mapped |= mapped;
    normals.x[i] = tangent_normal.x;
    normals.y[i] = tangent_normal.y;
    normals.z[i] = tangent_normal.z;
    normals.mapped[i] = mapped ? 1.0f : 0.0f;
    batch.position[i] = {surfaces.px[i], surfaces.py[i], surfaces.pz[i]};
    batch.gx[i] = batch.nx[i] = surfaces.nx[i];
    batch.gy[i] = batch.ny[i] = surfaces.ny[i];
    batch.gz[i] = batch.nz[i] = surfaces.nz[i];
    batch.base_r[i] = m.base_color.r;
    batch.base_g[i] = m.base_color.g;
    batch.base_b[i] = m.base_color.b;
    batch.metallic[i] = m.metallic;
    batch.roughness[i] = m.roughness;
    batch.occlusion[i] = m.occlusion;
    batch.emissive_r[i] = m.emissive.r;
    batch.emissive_g[i] = m.emissive.g;
    batch.emissive_b[i] = m.emissive.b;
    batch.alpha[i] = material.alpha_mode == AlphaMode::Blend ? m.alpha : 1.0f;
  }
  if (any_mapped) apply_normal_maps(surfaces, normals, batch);
}

}  // namespace cr

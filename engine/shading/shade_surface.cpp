#include "engine/shading/shade_surface.h"

#include <cmath>

#include "engine/core/math_constants.h"
#include "engine/shading/brdf.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/material_eval.h"
#include "engine/shading/safe_normalize.h"
#include "engine/shading/specular_occlusion.h"

namespace cr {
namespace {

// Least n.v shaded: normal maps and interpolated normals can face away from
// the viewer, where the BRDF is undefined; such normals are bent back just
// far enough to be seen (a cheap form of the usual "visible normal" fix).
constexpr float kMinNdotV = 1e-3f;

// Sum of SH coefficients times the basis at d, in ShLighting's order.
inline void sh_sum(const ShCoefficients& c, float dx, float dy, float dz, float& r, float& g, float& b) {
  const std::array<float, 9> y = sh_basis(glm::vec3(dx, dy, dz));
  r = c[0].r * y[0];
  g = c[0].g * y[0];
  b = c[0].b * y[0];
  for (size_t k = 1; k < 9; ++k) {
    r += c[k].r * y[k];
    g += c[k].g * y[k];
    b += c[k].b * y[k];
  }
}

// The batch's interpolated normals made unit: normalize_or(g, +Y) per lane,
// the same floats as safe_normalize.h's rule (|g| = sqrt((x x + y y) + z z)).
void normalize_interpolated_normals(ShadingBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    const float x = s.gx[i], y = s.gy[i], z = s.gz[i];
    const float len = std::sqrt(x * x + y * y + z * z);
    const bool ok = usable_length(len);
    s.gx[i] = ok ? x / len : 0.0f;
    s.gy[i] = ok ? y / len : 1.0f;
    s.gz[i] = ok ? z / len : 0.0f;
  }
}

// View vectors and the normals bent towards the viewer (kMinNdotV); n.l.
void view_and_normals(ShadingBatch& s, glm::dvec3 camera,
                                                                         glm::vec3 l, float* vx, float* vy,
                                                                         float* vz, float* n_dot_l) {
  for (int i = 0; i < s.count; ++i) {
    const glm::vec3 g(s.gx[i], s.gy[i], s.gz[i]);
    const float dx = float(camera.x - double(s.position[i].x));
    const float dy = float(camera.y - double(s.position[i].y));
    const float dz = float(camera.z - double(s.position[i].z));
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool ok = usable_length(len);
    const float x = ok ? dx / len : g.x, y = ok ? dy / len : g.y, z = ok ? dz / len : g.z;
    float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float n_dot_v = nx * x + ny * y + nz * z;
    const float push = kMinNdotV - n_dot_v;
    const float bx = nx + x * push, by = ny + y * push, bz = nz + z * push;
    const float blen = std::sqrt(bx * bx + by * by + bz * bz);
    const bool bok = usable_length(blen);
    const bool bend = !(n_dot_v >= kMinNdotV);
    nx = bend ? (bok ? bx / blen : x) : nx;
    ny = bend ? (bok ? by / blen : y) : ny;
    nz = bend ? (bok ? bz / blen : z) : nz;
    s.nx[i] = nx;
    s.ny[i] = ny;
    s.nz[i] = nz;
    vx[i] = x;
    vy[i] = y;
    vz[i] = z;
    n_dot_l[i] = nx * l.x + ny * l.y + nz * l.z;
  }
}

// No light reaches unlit points: n.l = 0 keeps them from the sun and its shadow.
// (Both unlit loops out of line: inlined, they cost the batch's other loops
// more than they take, even when skipped.)
[[gnu::noinline]] void darken_unlit(const ShadingBatch& s, float* n_dot_l) {
  for (int i = 0; i < s.count; ++i) n_dot_l[i] = s.unlit[i] != 0.0f ? 0.0f : n_dot_l[i];
}

// Unlit points' radiance: their emissive terms (base colour * the emissive
// luminance), in place of what lighting gave.
[[gnu::noinline]] void unlit_radiance(ShadingBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    const bool unlit = s.unlit[i] != 0.0f;
    s.out_r[i] = unlit ? finite_or_zero(s.emissive_r[i]) : s.out_r[i];
    s.out_g[i] = unlit ? finite_or_zero(s.emissive_g[i]) : s.out_g[i];
    s.out_b[i] = unlit ? finite_or_zero(s.emissive_b[i]) : s.out_b[i];
  }
}

// The specular ambient's incoming radiance without an environment: the SH
// radiance in the mirror direction, clamped at 0.
void sh_specular_radiance(const ShadingBatch& s, const ShCoefficients& radiance, const float* vx, const float* vy,
                          const float* vz, float* out_r, float* out_g, float* out_b) {
  for (int i = 0; i < s.count; ++i) {
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float two_ndv = 2.0f * (nx * vx[i] + ny * vy[i] + nz * vz[i]);
    float r, g, b;
    sh_sum(radiance, two_ndv * nx - vx[i], two_ndv * ny - vy[i], two_ndv * nz - vz[i], r, g, b);
    out_r[i] = std::max(r, 0.0f);
    out_g[i] = std::max(g, 0.0f);
    out_b[i] = std::max(b, 0.0f);
  }
}

// The specular ambient's incoming radiance from the prefiltered environment
// at the lobe's roughness, along the mirror direction bent towards the normal
// by alpha (Filament's dominant direction: the GGX lobe of a rough surface
// leans towards n, which the prefilter's n = v = R assumption loses).
void environment_specular_radiance(const ShadingBatch& s, const SpecularEnvironment& env, const float* vx,
                                   const float* vy, const float* vz, float* out_r, float* out_g, float* out_b) {
  constexpr int kN = ShadingBatch::kCapacity;
  float dx[kN], dy[kN], dz[kN], roughness[kN];
  for (int i = 0; i < s.count; ++i) {
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float two_ndv = 2.0f * (nx * vx[i] + ny * vy[i] + nz * vz[i]);
    const float rx = two_ndv * nx - vx[i], ry = two_ndv * ny - vy[i], rz = two_ndv * nz - vz[i];
    const float r = clamp_nan_safe(s.roughness[i], kMinRoughness, 1.0f);
    const float alpha = r * r;
    dx[i] = rx + (nx - rx) * alpha;
    dy[i] = ry + (ny - ry) * alpha;
    dz[i] = rz + (nz - rz) * alpha;
    roughness[i] = r;
  }
  env.sample_batch(size_t(s.count), dx, dy, dz, roughness, out_r, out_g, out_b);
}

struct LightingConstants {
  glm::vec3 l;
  const ShCoefficients* irradiance;
  const DfgTable* dfg;
};

// The sun through the BRDF plus the ambient and emission, per lane; spec_*
// hold the specular ambient's incoming radiance.
void light_points(ShadingBatch& s, const LightingConstants& c, const float* vx, const float* vy, const float* vz,
                  const float* n_dot_l, const float* sun_r, const float* sun_g, const float* sun_b,
                  const float* spec_r, const float* spec_g, const float* spec_b) {
  const glm::vec3 l = c.l;
  constexpr int kN = ShadingBatch::kCapacity;
  float rough[kN], ndv_c[kN], env_a[kN], env_b[kN];
  for (int i = 0; i < s.count; ++i) {
    rough[i] = clamp_nan_safe(s.roughness[i], kMinRoughness, 1.0f);
    ndv_c[i] = std::max(s.nx[i] * vx[i] + s.ny[i] * vy[i] + s.nz[i] * vz[i], kMinNdotV);
  }
  c.dfg->lookup_batch(size_t(s.count), rough, ndv_c, env_a, env_b);
  for (int i = 0; i < s.count; ++i) {
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float ndl = n_dot_l[i];
    const float ndv = nx * vx[i] + ny * vy[i] + nz * vz[i];
    const float metallic = s.metallic[i];
    const float m = clamp_nan_safe(metallic, 0.0f, 1.0f);
    const float br = s.base_r[i], bg = s.base_g[i], bb = s.base_b[i];
    const float f0r = channel_f0(br, m), f0g = channel_f0(bg, m), f0b = channel_f0(bb, m);

    // Direct sun (sun_* already hold E_sun * shadow visibility, 0 where it does not reach).
    const LightReflection sun =
        light_reflection(nx, ny, nz, vx[i], vy[i], vz[i], l.x, l.y, l.z, ndl, ndv, metallic, s.roughness[i]);
    float r = s.emissive_r[i] + reflected(sun, br, f0r) * sun_r[i];
    float g = s.emissive_g[i] + reflected(sun, bg, f0g) * sun_g[i];
    float b = s.emissive_b[i] + reflected(sun, bb, f0b) * sun_b[i];

    // Ambient: SH irradiance (diffuse) under the AO, the specular radiance
    // through the split-sum albedo under the specular occlusion.
    const float ea = env_a[i], eb_ = env_b[i];
    float er, eg, eb;
    sh_sum(*c.irradiance, nx, ny, nz, er, eg, eb);
    const float diffuse = (1.0f - metallic) * (1.0f - (kDielectricF0 * ea + eb_)) / kPi;
    const float ao = s.occlusion[i];
    const float so = specular_occlusion(ndv_c[i], ao, rough[i] * rough[i]);
    r += std::max(er, 0.0f) * diffuse * br * ao + spec_r[i] * (f0r * ea + eb_) * so;
    g += std::max(eg, 0.0f) * diffuse * bg * ao + spec_g[i] * (f0g * ea + eb_) * so;
    b += std::max(eb, 0.0f) * diffuse * bb * ao + spec_b[i] * (f0b * ea + eb_) * so;
    s.out_r[i] = finite_or_zero(r);
    s.out_g[i] = finite_or_zero(g);
    s.out_b[i] = finite_or_zero(b);
  }
}

}  // namespace

SurfaceShader::SurfaceShader(const ShadingInputs& in)
    : scene_(in.scene),
      light_(in.light),
      shadow_(in.shadow && in.shadow->size > 0 ? in.shadow : nullptr),
      camera_position_(in.camera_position),
      emissive_luminance_(in.emissive_luminance),
      sun_direction_(normalize_or(in.light->sun_direction, glm::vec3(0.0f, 1.0f, 0.0f))),
      ambient_(in.light->ambient_sh),
      specular_(in.light->specular.get()),
      dfg_(&DfgTable::get()) {
  for (const PunctualLight& light : scene_->lights) lights_.push_back(punctual_light_terms(light));
}

void SurfaceShader::add(ShadingBatch& batch, const Material& material, const SurfaceSample& surface) const {
  const MaterialSample m = evaluate_material(*scene_, material, surface, emissive_luminance_);
  batch.add(surface, m, material.alpha_mode == AlphaMode::Blend ? m.alpha : 1.0f);
}

void SurfaceShader::shade_batch(ShadingBatch& batch) const {
  constexpr int kN = ShadingBatch::kCapacity;
  const int n = batch.count;
  float vx[kN], vy[kN], vz[kN], n_dot_l[kN];
  normalize_interpolated_normals(batch);
  view_and_normals(batch, camera_position_, sun_direction_, vx, vy, vz, n_dot_l);
  if (batch.any_unlit) darken_unlit(batch, n_dot_l);

  // The sun's illuminance times its visibility, fetched for lit points only.
  float sun_r[kN], sun_g[kN], sun_b[kN];
  int lit[kN];
  glm::vec3 lit_position[kN], lit_sun[kN];
  int lit_count = 0;
  for (int i = 0; i < n; ++i) {
    sun_r[i] = sun_g[i] = sun_b[i] = 0.0f;
    if (n_dot_l[i] > 0.0f) {
      lit_position[lit_count] = batch.position[i];
      lit[lit_count++] = i;
    }
  }
  if (light_->sun_at)
    light_->sun_at(lit_position, lit_sun, size_t(lit_count));
  else
    for (int k = 0; k < lit_count; ++k) lit_sun[k] = light_->sun_illuminance;
  // The shadow lookup uses the interpolated normal: its bias models the
  // geometry in the depth map, which the normal map does not change.
  static_assert(ShadowReceivers::kCapacity >= kN);
  ShadowReceivers receivers;
  int receiver_of[kN];  // lit entry -> receiver, or -1 where the sun is dark
  for (int k = 0; k < lit_count; ++k) {
    receiver_of[k] = -1;
    if (!shadow_ || lit_sun[k] == glm::vec3(0.0f)) continue;
    const int i = lit[k], j = receivers.count++;
    receivers.px[j] = batch.position[i].x;
    receivers.py[j] = batch.position[i].y;
    receivers.pz[j] = batch.position[i].z;
    receivers.nx[j] = batch.gx[i];
    receivers.ny[j] = batch.gy[i];
    receivers.nz[j] = batch.gz[i];
    receiver_of[k] = j;
  }
  float visibility[kN];
  if (receivers.count > 0) shadow_->visibility(receivers, visibility);
  for (int k = 0; k < lit_count; ++k) {
    const int i = lit[k];
    glm::vec3 e = lit_sun[k];
    if (receiver_of[k] >= 0) e *= visibility[receiver_of[k]];
    sun_r[i] = e.r;
    sun_g[i] = e.g;
    sun_b[i] = e.b;
  }

  float spec_r[kN], spec_g[kN], spec_b[kN];
  if (specular_)
    environment_specular_radiance(batch, *specular_, vx, vy, vz, spec_r, spec_g, spec_b);
  else
    sh_specular_radiance(batch, ambient_.radiance_coefficients(), vx, vy, vz, spec_r, spec_g, spec_b);
  const LightingConstants constants{sun_direction_, &ambient_.irradiance_coefficients(), dfg_};
  light_points(batch, constants, vx, vy, vz, n_dot_l, sun_r, sun_g, sun_b, spec_r, spec_g, spec_b);
  if (!lights_.empty()) add_punctual_lights(batch, lights_.data(), lights_.size(), vx, vy, vz);
  if (batch.any_unlit) unlit_radiance(batch);
}

glm::vec4 SurfaceShader::shade(const Material& material, const SurfaceSample& surface) const {
  ShadingBatch batch;
  add(batch, material, surface);
  shade_batch(batch);
  return {batch.radiance(0), batch.alpha[0]};
}

glm::vec4 shade_surface(const ShadingInputs& in, const Material& material, const SurfaceSample& surface) {
  return SurfaceShader(in).shade(material, surface);
}

}  // namespace cr

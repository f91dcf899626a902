#include "engine/shading/punctual_lights.h"

#include <algorithm>
#include <cmath>

#include "engine/shading/safe_normalize.h"

namespace cr {
namespace {

// One light over every point of the batch: a vectorised loop (out of line so
// that the restricts hold).
[[gnu::noinline]] void add_light(ShadingBatch& __restrict s, const PunctualLightTerms& light,
                                 const float* __restrict vx, const float* __restrict vy,
                                 const float* __restrict vz) {
  const glm::vec3 p = light.position, e = light.intensity, axis = light.direction;
  const float inv_range = light.inv_range, cone_scale = light.cone_scale, cone_offset = light.cone_offset;
  for (int i = 0; i < s.count; ++i) {
    const float dx = p.x - s.position[i].x, dy = p.y - s.position[i].y, dz = p.z - s.position[i].z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    const float d = std::sqrt(d2);
    const bool ok = usable_length(d);
    const float inv_d = ok ? 1.0f / d : 0.0f;
    const float lx = dx * inv_d, ly = dy * inv_d, lz = dz * inv_d;
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float n_dot_l = nx * lx + ny * ly + nz * lz;
    const float n_dot_v = nx * vx[i] + ny * vy[i] + nz * vz[i];
    // The cone's angle is between its axis and the ray from the light, -l.
    const float cos_angle = -(axis.x * lx + axis.y * ly + axis.z * lz);
    const float attenuation = range_window(d, inv_range) * cone_attenuation(cos_angle, cone_scale, cone_offset);
    const float falloff = ok ? attenuation / d2 : 0.0f;
    const LightReflection r = light_reflection(nx, ny, nz, vx[i], vy[i], vz[i], lx, ly, lz, n_dot_l, n_dot_v,
                                               s.metallic[i], s.roughness[i]);
    const float m = clamp_nan_safe(s.metallic[i], 0.0f, 1.0f);
    const float br = s.base_r[i], bg = s.base_g[i], bb = s.base_b[i];
    s.out_r[i] = finite_or_zero(s.out_r[i] + reflected(r, br, channel_f0(br, m)) * (e.r * falloff));
    s.out_g[i] = finite_or_zero(s.out_g[i] + reflected(r, bg, channel_f0(bg, m)) * (e.g * falloff));
    s.out_b[i] = finite_or_zero(s.out_b[i] + reflected(r, bb, channel_f0(bb, m)) * (e.b * falloff));
  }
}

}  // namespace

PunctualLightTerms punctual_light_terms(const PunctualLight& light) {
  PunctualLightTerms t;
  t.position = light.position;
  t.intensity = light.color * light.intensity;
  t.inv_range = light.range > 0.0f ? 1.0f / light.range : 0.0f;
  t.direction = normalize_or(light.direction, glm::vec3(0.0f, 0.0f, -1.0f));
  if (light.type == PunctualLight::Type::Spot) {
    const float cos_outer = std::cos(light.outer_cone_rad), cos_inner = std::cos(light.inner_cone_rad);
    t.cone_scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
    t.cone_offset = -cos_outer * t.cone_scale;
  }
  return t;
}

void add_punctual_lights(ShadingBatch& batch, const PunctualLightTerms* lights, size_t count, const float* vx,
                         const float* vy, const float* vz) {
  for (size_t k = 0; k < count; ++k) add_light(batch, lights[k], vx, vy, vz);
}

}  // namespace cr

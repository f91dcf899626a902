#include "atmosphere/sky_composite.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>


#include "atmosphere/float4.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/q15_texels.h"
#include "engine/core/fast_math.h"
#include "engine/core/fixed_point.h"

namespace cr {

namespace {

// Per-pixel ray march (space fallback for geometry, and geometry beyond the AP range).
RayScattering march_pixel(const SkyFrame& f, const glm::vec3& dir, double max_distance) {
  thread_local MarchedRay scratch;
  const AtmosphereLuts luts{f.model, *f.ms_transmittance, *f.multiscattering};
  const double mu = glm::dot(glm::dvec3(dir), f.camera_position / glm::length(f.camera_position));
  const double nu = std::clamp(double(glm::dot(dir, f.sun)), -1.0, 1.0);
  const int steps = std::max(f.space_steps, f.skyview_max_steps);
  return integrate_ray(luts, f.camera_radius, mu, f.mu_s, nu, max_distance, f.skyview_min_steps, steps, scratch);
}

glm::vec3 skyview_lookup(const SkyFrame& f, const glm::vec3& dir) {
  const float cos_vz = std::clamp(glm::dot(dir, f.up), -1.0f, 1.0f);
  const float sin_vz = std::sqrt(std::max(0.0f, 1.0f - cos_vz * cos_vz));
  const float cos_lon = sin_vz > 1e-6f ? glm::dot(dir, f.sun_horizontal) / sin_vz : 1.0f;
  const float nu = std::clamp(glm::dot(dir, f.sun), -1.0f, 1.0f);
  const glm::vec2 unit = f.skyview->mapping().to_unit(cos_vz, cos_lon);
  const float phase = mie_phase(f.model, nu);
  return f.fixed ? f.skyview->sample_fixed(unit, phase) : f.skyview->sample(unit, phase);
}

// skyview_lookup()'s LUT coordinates (unit square) and Mie phase of n
// directions, with its operations in its order (glm::dot is (x + y) + z).
// Selects, restrict pointers, out of line: it vectorizes.
template <class Phase>
__attribute__((noinline)) void skyview_coordinates(const SkyFrame& f, const Phase& phase, size_t n,
                                                   const float* __restrict dx, const float* __restrict dy,
                                                   const float* __restrict dz, float* __restrict u,
                                                   float* __restrict v, float* __restrict ph) {
  const SkyViewMapping map = f.skyview->mapping();
  const glm::vec3 up = f.up, sun = f.sun, sun_h = f.sun_horizontal;
  for (size_t i = 0; i < n; ++i) {
    float cos_vz = dx[i] * up.x + dy[i] * up.y + dz[i] * up.z;
    cos_vz = cos_vz < -1.0f ? -1.0f : (1.0f < cos_vz ? 1.0f : cos_vz);
    const float sin2 = 1.0f - cos_vz * cos_vz;
    const float sin_vz = std::sqrt(0.0f < sin2 ? sin2 : 0.0f);
    const float along = dx[i] * sun_h.x + dy[i] * sun_h.y + dz[i] * sun_h.z;
    const float cos_lon = sin_vz > 1e-6f ? along / (sin_vz > 1e-6f ? sin_vz : 1.0f) : 1.0f;
    float nu = dx[i] * sun.x + dy[i] * sun.y + dz[i] * sun.z;
    nu = nu < -1.0f ? -1.0f : (1.0f < nu ? 1.0f : nu);
    const glm::vec2 unit = map.to_unit(cos_vz, cos_lon);
    u[i] = unit.x;
    v[i] = unit.y;
    ph[i] = phase(nu);
  }
}

struct FroxelSample {
  glm::vec3 luminance;
  glm::vec3 transmittance;
};

FroxelSample sample_froxels(const AerialPerspectiveLut& ap, const LutCoord& cx, const LutCoord& cy, float distance) {
  const LutImage& L = ap.luminance();
  const LutImage& T = ap.transmittance();
  const float sz = ap.slice_coordinate(distance);
  if (sz < 0.0f) {
    // Between the camera (nothing scattered, T = 1) and the first slice: linear in distance.
    const float w = std::clamp(distance / ap.slice_distance(0), 0.0f, 1.0f);
    return {sample_bilinear(L, cx, cy, 0) * w, glm::mix(glm::vec3(1.0f), sample_bilinear(T, cx, cy, 0), w)};
  }
  const LutCoord cz = lut_coord(sz, L.depth);
  const glm::vec3 l = glm::mix(sample_bilinear(L, cx, cy, cz.i0), sample_bilinear(L, cx, cy, cz.i1), cz.w);
  const glm::vec3 t = glm::mix(sample_bilinear(T, cx, cy, cz.i0), sample_bilinear(T, cx, cy, cz.i1), cz.w);
  return {l, t};
}

// sample_froxels() from the q15 froxels: the footprint's weights in q15, the
// bi/trilinear blend of luminance and transmittance as one 8-code vector,
// then decoded; the near-camera weight in float, as the fixed kernel does.
FroxelSample sample_froxels_fixed(const AerialPerspectiveLut& ap, const LutCoord& cx, const LutCoord& cy,
                                  float distance) {
  const FroxelTexelQ15* q = ap.packed_q15().data();
  const int depth = ap.luminance().depth;
  const fx::I16x8 wx = splat_weight(fx::weight_q15(cx.w)), wy = splat_weight(fx::weight_q15(cy.w));
  auto slice = [&](int z) {
    return bilinear_q15(&q[ap.packed_index(cx.i0, cy.i0, z)], &q[ap.packed_index(cx.i1, cy.i0, z)],
                        &q[ap.packed_index(cx.i0, cy.i1, z)], &q[ap.packed_index(cx.i1, cy.i1, z)], wx, wy);
  };
  const float sz = ap.slice_coordinate(distance);
  fx::U16x8 v;
  float near = 1.0f;
  if (sz < 0.0f) {
    v = slice(0);
    near = std::clamp(distance / ap.slice_distance(0), 0.0f, 1.0f);
  } else {
    const LutCoord cz = lut_coord(sz, depth);
    v = fx::lerp_q15(slice(cz.i0), slice(cz.i1), splat_weight(fx::weight_q15(cz.w)));
  }
  Float4 l, t;
  decode_halves(v, ap.luminance_scale().scale, 1.0f, l, t);
  l *= splat4(near);
  const Float4 one = {1.0f, 1.0f, 1.0f, 0.0f};
  return {to_vec3(l), to_vec3(one + (t - one) * splat4(near))};
}

// Froxel texel coordinates of a world point given relative to the froxel camera.
void project_to_froxels(const AerialPerspectiveLut& ap, const glm::vec3& rel, float& fx, float& fy) {
  const FroxelCamera& c = ap.camera();
  const float z = std::max(glm::dot(rel, c.forward), 1e-6f * glm::length(rel) + 1e-30f);
  const float sx = glm::dot(rel, c.right) / (z * c.tan_half_fov * c.aspect);
  const float sy = glm::dot(rel, c.up) / (z * c.tan_half_fov);
  fx = (sx + 1.0f) * 0.5f * float(ap.luminance().width) - 0.5f;
  fy = (1.0f - sy) * 0.5f * float(ap.luminance().height) - 0.5f;
}

// A vector's dot product with a pixel's unnormalised view direction
// base + sx * right is linear in sx: a0 + sx * a1, constant over a row.
struct RowDot {
  float a0 = 0.0f, a1 = 0.0f;
  RowDot() = default;
  RowDot(const glm::vec3& a, const glm::vec3& base, const glm::vec3& right)
      : a0(glm::dot(a, base)), a1(glm::dot(a, right)) {}
};

inline float clamp_texel(float x, float hi) { return x > 0.0f ? (x < hi ? x : hi) : 0.0f; }  // NaN -> 0

// Sky-view texel coordinates, Mie phase and sun cosine of `n` sky pixels.
// Branch-free, restrict pointers: it vectorizes.
struct SkyRow {
  RowDot up, sun, sun_h;
  float len0, len1, len2;  // |base + sx right|^2 = len0 + sx (len1 + sx len2)
  float first_angle, inv_above, zha, inv_beta, u_scale, v_scale;
};

template <class Phase>
void sky_coordinates(const SkyRow& c, const Phase& phase, size_t n, const float* __restrict sx,
                     float* __restrict fu, float* __restrict fv, float* __restrict ph, float* __restrict nu_out) {
  for (size_t j = 0; j < n; ++j) {
    const float s = sx[j];
    const float inv_len = 1.0f / std::sqrt(c.len0 + s * (c.len1 + s * c.len2));
    float cos_vz = (c.up.a0 + s * c.up.a1) * inv_len;
    cos_vz = cos_vz < -1.0f ? -1.0f : (cos_vz > 1.0f ? 1.0f : cos_vz);
    float nu = (c.sun.a0 + s * c.sun.a1) * inv_len;
    nu = nu < -1.0f ? -1.0f : (nu > 1.0f ? 1.0f : nu);
    const float along = (c.sun_h.a0 + s * c.sun_h.a1) * inv_len;
    const float sin_vz = std::sqrt(1.0f - cos_vz * cos_vz);
    const float cos_lon = sin_vz > 1e-6f ? along / (sin_vz > 1e-6f ? sin_vz : 1.0f) : 1.0f;
    const float angle = fast_acos(cos_vz);
    const float above = 1.0f - (angle - c.first_angle) * c.inv_above;
    const float below = (angle - c.zha) * c.inv_beta;
    const float v = angle < c.zha ? 0.5f - 0.5f * std::sqrt(above > 0.0f ? (above < 1.0f ? above : 1.0f) : 0.0f)
                                  : 0.5f + 0.5f * std::sqrt(below < 1.0f ? below : 1.0f);
    float uu = 0.5f - 0.5f * cos_lon;
    uu = uu < 0.0f ? 0.0f : (uu > 1.0f ? 1.0f : uu);
    fu[j] = std::sqrt(uu) * c.u_scale;
    fv[j] = v * c.v_scale;
    ph[j] = phase(nu);
    nu_out[j] = nu;
  }
}

// Aerial perspective from the froxels for `n` opaque pixels of a row.
//
// Froxel texel coordinates: the froxel camera may lag the frame's camera
// under an amortised schedule (by less than the invalidation thresholds:
// 50 m, 5 deg): the pixel's direction is reprojected into it and the distance
// kept; the offset of the two positions moves the sample by at most those
// 50 m, where aerial perspective changes over kilometres. Between the camera
// and the first slice a weight scales the first slice (T = 1 and nothing
// scattered at the camera).
struct FroxelRow {
  RowDot fwd, right, up;
  float x_scale, x_bias, y_scale, y_bias;
  float inv_extent, depth, max_slice, inv_first_slice, max_x, max_y;
};

// The packed froxel volume (see AerialPerspectiveLut::packed()).
struct FroxelVolume {
  const FroxelTexel* texels;
  int width, height;  // of the LUT; the packed rows hold width + 1 texels, the slices height + 1 rows
};

// Bilinear blend of the froxel texels at r, r + dx, r + dy, r + dx + dy
// (offsets in floats): luminance (floats 0-3) and transmittance (4-7) as two
// SSE vectors. (An 8-float vector would be one AVX operation, but built for
// the SSE baseline GCC splits it through the stack, and the reloads stall.)
inline void bilinear_froxel(const float* r, size_t dx, size_t dy, const Float4& wx, const Float4& wy, Float4& l,
                            Float4& t) {
  const Float4 la = load4(r), lb = load4(r + dx), lc = load4(r + dy), ld = load4(r + dy + dx);
  const Float4 ta = load4(r + 4), tb = load4(r + dx + 4), tc = load4(r + dy + 4), td = load4(r + dy + dx + 4);
  const Float4 l_top = la + (lb - la) * wx, l_bottom = lc + (ld - lc) * wx;
  const Float4 t_top = ta + (tb - ta) * wx, t_bottom = tc + (td - tc) * wx;
  l = l_top + (l_bottom - l_top) * wy;
  t = t_top + (t_bottom - t_top) * wy;
}

// Per-tile working memory, one per thread.
struct Scratch {
  std::vector<float> sx, row_sx, dist, a, b, c, d;
  std::vector<int> sky, interp, froxel, other, identity, texel;
  std::vector<int16_t> qx, qy, qz;  // q15 froxel weights (fixed composite)
  std::vector<glm::vec3> grid;       // exact sky at the grid points
  std::vector<glm::vec3> edge;       // the grid interpolated to one row
  std::vector<float> wx;             // per pixel: weight of the grid column to its right
  std::vector<uint8_t> grid_above;   // grid point above the horizon
  std::vector<float> grid_nu;        // cosine to the sun at the grid points
  std::vector<uint8_t> block_exact;  // per block: evaluate every pixel
  std::vector<float> dir_x, dir_y, dir_z;  // directions of the grid points, then of the tested block centres
  std::vector<glm::vec3> centre;           // exact sky at the tested block centres
  std::vector<int> tested;                 // blocks whose centre is tested
  void resize(size_t n) {
    for (auto* v : {&sx, &row_sx, &dist, &a, &b, &c, &d}) v->resize(n);
    for (auto* v : {&sky, &interp, &froxel, &other, &texel}) v->resize(n);
    for (auto* v : {&qx, &qy, &qz}) v->resize(n);
    for (size_t k = identity.size(); k < n; ++k) identity.push_back(int(k));
  }
};

// Froxel footprints of the pixels at screen x sx[j] and distance dist[j]:
// packed index of the first texel, trilinear weights, near-camera weight.
// Branch-free, restrict pointers: it vectorizes.
inline void froxel_footprints(const FroxelRow& c, const FroxelVolume& v, size_t n, const float* __restrict sx,
                              const float* __restrict dist, int* __restrict texel, float* __restrict wx,
                              float* __restrict wy, float* __restrict wz, float* __restrict near_w) {
  const int row = v.width + 1, slice = row * (v.height + 1);
  for (size_t j = 0; j < n; ++j) {
    const float s = sx[j];
    const float z = c.fwd.a0 + s * c.fwd.a1;
    const float zc = z > 1e-6f ? z : 1e-6f;  // behind the froxel camera: clamp to its frustum edge
    const float inv_z = 1.0f / zc;
    const float fx = clamp_texel((c.right.a0 + s * c.right.a1) * inv_z * c.x_scale + c.x_bias, c.max_x);
    const float fy = clamp_texel((c.up.a0 + s * c.up.a1) * inv_z * c.y_scale + c.y_bias, c.max_y);
    const float d = dist[j];
    const float sz = std::sqrt(d * c.inv_extent) * c.depth - 0.5f;
    const float fz = clamp_texel(sz, c.max_slice);
    const int ix = int(fx), iy = int(fy), iz = int(fz);
    texel[j] = iz * slice + iy * row + ix;
    wx[j] = fx - float(ix);
    wy[j] = fy - float(iy);
    wz[j] = fz - float(iz);
    const float w = d * c.inv_first_slice;
    near_w[j] = sz < 0.0f ? w : 1.0f;
  }
}

// Applies the froxels to color[index[j]] of the pixels at screen x sx[j] and
// distance dist[j]: the footprints first, then the trilinear blends. A pixel
// whose depth weight is 0 (closer than the first slice, or at the last) reads
// one slice: the other would add (back - front) * 0.
void apply_froxels(const FroxelRow& c, const FroxelVolume& v, size_t n, const int* __restrict index,
                   const float* __restrict sx, const float* __restrict dist, Scratch& s, const Float4& illuminance,
                   glm::vec3* __restrict color) {
  int* texel = s.texel.data();
  float *wx = s.a.data(), *wy = s.b.data(), *wz = s.c.data(), *near_w = s.d.data();
  froxel_footprints(c, v, n, sx, dist, texel, wx, wy, wz, near_w);
  const size_t row = size_t(v.width) + 1;
  const size_t dx = 8, dy = 8 * row, dz = 8 * row * (size_t(v.height) + 1);  // in floats
  const Float4 one = {1.0f, 1.0f, 1.0f, 0.0f};
  const float* texels = reinterpret_cast<const float*>(v.texels);
  for (size_t j = 0; j < n; ++j) {
    const Float4 x4 = splat4(wx[j]), y4 = splat4(wy[j]);
    const float az = wz[j];
    const float* q = texels + 8 * size_t(texel[j]);
    Float4 l, t;
    bilinear_froxel(q, dx, dy, x4, y4, l, t);
    if (az != 0.0f) {
      Float4 l_back, t_back;
      bilinear_froxel(q + dz, dx, dy, x4, y4, l_back, t_back);
      const Float4 z4 = splat4(az);
      l = l + (l_back - l) * z4;
      t = t + (t_back - t) * z4;
    }
    const Float4 near = splat4(near_w[j]);
    l = l * near;
    const Float4 tr = one + (t - one) * near;
    glm::vec3& out = color[index[j]];
    const Float4 r = to_float4(out) * tr + l * illuminance;
    out = to_vec3(r);
  }
}

// apply_froxels() from the q15 froxels (FroxelVolumeQ15: the same layout):
// weights converted to q15 in one loop that vectorizes, then per pixel the
// bi/trilinear blend of luminance and transmittance as one 8-code vector in
// 16-bit integer arithmetic (three or seven lerps), decoded, and the
// near-camera weight and the blend with the surface in float.
struct FroxelVolumeQ15 {
  const FroxelTexelQ15* texels;
  int width, height;
  float luminance_scale;
};

void apply_froxels_fixed(const FroxelRow& c, const FroxelVolumeQ15& v, size_t n, const int* __restrict index,
                         const float* __restrict sx, const float* __restrict dist, Scratch& s,
                         const Float4& illuminance, glm::vec3* __restrict color) {
  int* texel = s.texel.data();
  float *wx = s.a.data(), *wy = s.b.data(), *wz = s.c.data(), *near_w = s.d.data();
  froxel_footprints(c, FroxelVolume{nullptr, v.width, v.height}, n, sx, dist, texel, wx, wy, wz, near_w);
  int16_t *qx = s.qx.data(), *qy = s.qy.data(), *qz = s.qz.data();
  for (size_t j = 0; j < n; ++j) {
    qx[j] = fx::weight_q15(wx[j]);
    qy[j] = fx::weight_q15(wy[j]);
    qz[j] = fx::weight_q15(wz[j]);
  }
  const size_t row = size_t(v.width) + 1;
  const size_t dy = row, dz = row * (size_t(v.height) + 1);  // in texels
  const Float4 one = {1.0f, 1.0f, 1.0f, 0.0f};
  for (size_t j = 0; j < n; ++j) {
    const fx::I16x8 x8 = splat_weight(qx[j]), y8 = splat_weight(qy[j]);
    const FroxelTexelQ15* q = v.texels + size_t(texel[j]);
    fx::U16x8 lt = bilinear_q15(q, q + 1, q + dy, q + dy + 1, x8, y8);
    if (qz[j] != 0) {
      const FroxelTexelQ15* b = q + dz;
      lt = fx::lerp_q15(lt, bilinear_q15(b, b + 1, b + dy, b + dy + 1, x8, y8), splat_weight(qz[j]));
    }
    const Float4 near = splat4(near_w[j]);
    Float4 l, t;
    decode_halves(lt, v.luminance_scale, 1.0f, l, t);
    l *= near;
    const Float4 tr = one + (t - one) * near;
    glm::vec3& out = color[index[j]];
    out = to_vec3(to_float4(out) * tr + l * illuminance);
  }
}

// The sky over a tile is smooth almost everywhere: it is evaluated exactly on
// a grid of every kBlock-th pixel and bilinearly interpolated inside each
// block, except in blocks where that is not accurate: across the horizon (or
// the planet's limb), near the sun disk, or where the block centre's exact
// value departs from the interpolation (the forward Mie peak); those are
// evaluated per pixel.
constexpr int kBlock = 8;
constexpr int kPrefetchRows = 4;
constexpr float kBlockTolerance = 3e-3f;  // relative, at the block centre: far below the LUT's own error

// Grid coordinate i of a span starting at pixel a, in a frame `edge` pixels
// wide: pixel a + i * kBlock, clamped to the frame's last pixel. Grid points
// past the span's end belong to the frame, not the span, so where spans start
// at multiples of kBlock (the composite pass's strips do) every pixel gets
// the same grid whichever way the frame is split.
inline int grid_pixel(int a, int edge, int i) { return std::min(a + i * kBlock, edge - 1); }

}  // namespace

glm::vec3 sun_disk_radiance(const SkyFrame& f, const glm::vec3& dir) {
  const float c = glm::dot(dir, f.sun);
  if (c <= f.cos_sun_radius) return glm::vec3(0.0f);
  // sin^2 of the angle to the centre over sin^2 of the disk radius -> cos on the solar surface.
  const float ratio = (1.0f - c * c) / (1.0f - f.cos_sun_radius * f.cos_sun_radius);
  return sun_disk_limb(f.sun_disk_center, std::sqrt(std::max(0.0f, 1.0f - ratio)));
}

glm::vec3 sky_radiance(const SkyFrame& f, const glm::vec3& dir, bool with_sun_disk) {
  if (!f.valid) return glm::vec3(0.0f);
  glm::vec3 l = skyview_lookup(f, dir) * f.sun_illuminance;
  const float mu = glm::dot(dir, f.up);
  if (with_sun_disk && mu > f.mu_horizon) {
    const glm::vec3 disk = sun_disk_radiance(f, dir);
    if (disk != glm::vec3(0.0f)) l += disk * f.transmittance->to_top(f.camera_row, mu);
  }
  return l;
}

void sky_radiance_batch(const SkyFrame& f, size_t n, const float* dx, const float* dy, const float* dz,
                        glm::vec3* out) {
  if (!f.valid) {
    std::fill(out, out + n, glm::vec3(0.0f));
    return;
  }
  thread_local std::vector<float> u, v, ph;
  u.resize(n);
  v.resize(n);
  ph.resize(n);
  const AtmosphereModel& m = f.model;
  if (m.mie_phase == MiePhaseModel::CornetteShanks)
    skyview_coordinates(f, [g = m.mie_g](float c) { return cornette_shanks(c, g); }, n, dx, dy, dz, u.data(),
                        v.data(), ph.data());
  else
    skyview_coordinates(
        f,
        [g = m.mie_g, g2 = m.mie_g2, lobe = m.mie_lobe_weight](float c) {
          return lobe * henyey_greenstein(c, g) + (1.0f - lobe) * henyey_greenstein(c, g2);
        },
        n, dx, dy, dz, u.data(), v.data(), ph.data());
  if (f.fixed)
    for (size_t i = 0; i < n; ++i) out[i] = f.skyview->sample_fixed(glm::vec2(u[i], v[i]), ph[i]) * f.sun_illuminance;
  else
    for (size_t i = 0; i < n; ++i) out[i] = f.skyview->sample(glm::vec2(u[i], v[i]), ph[i]) * f.sun_illuminance;
}

glm::vec3 apply_aerial_perspective(const SkyFrame& f, const glm::vec3& dir, float distance, const glm::vec3& color) {
  if (!f.valid) return color;
  if (f.space) {
    const RayScattering s = march_pixel(f, dir, distance);
    return color * s.transmittance + s.luminance * f.sun_illuminance;
  }
  const AerialPerspectiveLut& ap = *f.aerial_perspective;
  const glm::vec3 rel = glm::vec3(f.camera_position - ap.camera().position) + dir * distance;
  const float froxel_distance = glm::length(rel);
  float fx, fy;
  project_to_froxels(ap, rel, fx, fy);
  const float range = ap.range();
  const LutCoord cx = lut_coord(fx, ap.luminance().width), cy = lut_coord(fy, ap.luminance().height);
  FroxelSample s = f.fixed ? sample_froxels_fixed(ap, cx, cy, std::min(froxel_distance, range))
                           : sample_froxels(ap, cx, cy, std::min(froxel_distance, range));
  if (froxel_distance > range) {
    // Beyond the froxels: march the rest of the ray and append it.
    thread_local MarchedRay scratch;
    const AtmosphereLuts luts{f.model, *f.ms_transmittance, *f.multiscattering};
    const double mu = glm::dot(glm::dvec3(dir), f.camera_position / glm::length(f.camera_position));
    const double t_top = distance_to_sphere_exit(f.camera_radius, mu, f.model.top_radius);
    const float t_end = float(std::min(double(distance), std::max(t_top, double(range))));
    if (t_end > range) {
      const float nu = std::clamp(glm::dot(dir, f.sun), -1.0f, 1.0f);
      march(luts, f.camera_altitude, float(mu), range, t_end, f.space_steps, StepSpacing::Uniform, false,
            std::min(f.camera_altitude, 10.0f), scratch);
      s.luminance += s.transmittance * shade(luts, scratch, f.mu_s, nu);
      s.transmittance *= scratch.transmittance;
    }
  }
  return color * s.transmittance + s.luminance * f.sun_illuminance;
}

void composite_sky(const SkyFrame& f, FrameBuffers& buffers, int x0, int y0, int x1, int y1) {
  if (!f.valid || x1 <= x0 || y1 <= y0) return;
  const int w = buffers.width;
  const int h = buffers.height;
  const Camera& cam = f.camera;
  const float t = std::tan(0.5f * cam.vfov_rad);
  const size_t n = size_t(x1 - x0);
  thread_local Scratch s;
  s.resize(n);
  auto screen_x = [&](float px) { return (2.0f * (px + 0.5f) / float(w) - 1.0f) * t * cam.aspect; };
  auto screen_y = [&](float py) { return (1.0f - 2.0f * (py + 0.5f) / float(h)) * t; };
  for (size_t k = 0; k < n; ++k) s.sx[k] = screen_x(float(x0 + int(k)));
  const Float4 e = {f.sun_illuminance.x, f.sun_illuminance.y, f.sun_illuminance.z, 0.0f};

  const SkyViewLut& sv = *f.skyview;
  const SkyViewMapping& map = sv.mapping();
  const int sv_w = sv.image().width, sv_h = sv.image().height;
  const SkyViewTexel* sky_texels = sv.packed().data();
  const SkyViewTexelQ15* sky_q15 = f.fixed ? sv.packed_q15().data() : nullptr;
  const float rest_scale = sv.rest_scale().scale, mie_scale = sv.mie_scale().scale;
  SkyRow sr{RowDot(f.up, cam.forward, cam.right), RowDot(f.sun, cam.forward, cam.right),
            RowDot(f.sun_horizontal, cam.forward, cam.right), 0.0f, 0.0f, 0.0f, map.first_angle,
            1.0f / (map.zenith_horizon_angle - map.first_angle), map.zenith_horizon_angle, 1.0f / map.beta,
            float(sv_w - 1), float(sv_h - 1)};
  const AtmosphereModel& model = f.model;
  const bool mie_cornette_shanks = model.mie_phase == MiePhaseModel::CornetteShanks;
  const float g = model.mie_g, g2 = model.mie_g2, lobe = model.mie_lobe_weight;

  // The sky grid of this tile and which blocks need every pixel.
  const int nbx = (x1 - x0 + kBlock - 1) / kBlock, nby = (y1 - y0 + kBlock - 1) / kBlock;
  const size_t gw = size_t(nbx) + 1;
  s.grid.resize(gw * size_t(nby + 1));
  s.grid_above.resize(s.grid.size());
  s.grid_nu.resize(s.grid.size());
  s.block_exact.assign(size_t(nbx) * size_t(nby), 0);
  s.edge.resize(gw);
  s.wx.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const int bi = int(k) / kBlock;
    const int gx0 = grid_pixel(x0, w, bi) - x0, gx1 = grid_pixel(x0, w, bi + 1) - x0;
    s.wx[k] = gx1 > gx0 ? float(int(k) - gx0) / float(gx1 - gx0) : 0.0f;
  }
  const float cos_horizon = std::cos(map.zenith_horizon_angle);
  auto direction = [&](float px, float py) {
    return glm::normalize(cam.forward + screen_x(px) * cam.right + screen_y(py) * cam.up);
  };
  // Built when the first row with sky needs it: a tile of only geometry never does.
  bool grid_ready = false;
  // The grid points' and then the tested block centres' sky come from sky_radiance_batch (exactly sky_radiance).
  auto set_direction = [&](size_t k, const glm::vec3& dir) {
    s.dir_x[k] = dir.x;
    s.dir_y[k] = dir.y;
    s.dir_z[k] = dir.z;
  };
  auto build_grid = [&] {
    grid_ready = true;
    const size_t points = s.grid.size();
    for (auto* v : {&s.dir_x, &s.dir_y, &s.dir_z}) v->resize(std::max(points, size_t(nbx) * size_t(nby)));
    for (int j = 0; j <= nby; ++j)
      for (int i = 0; i <= nbx; ++i) {
        const glm::vec3 dir = direction(float(grid_pixel(x0, w, i)), float(grid_pixel(y0, h, j)));
        const size_t g_i = size_t(j) * gw + size_t(i);
        set_direction(g_i, dir);
        s.grid_above[g_i] = glm::dot(dir, f.up) > cos_horizon ? 1 : 0;
        s.grid_nu[g_i] = glm::dot(dir, f.sun);
      }
    sky_radiance_batch(f, points, s.dir_x.data(), s.dir_y.data(), s.dir_z.data(), s.grid.data());
    // A block's diagonal, as an angle (pixels are largest at the image centre).
    const float block_angle = 1.5f * float(kBlock) * 2.0f * t / float(h);
    const float cos_near_sun = std::cos(std::min(model.sun_angular_radius + block_angle, kPi));
    s.tested.clear();
    for (int j = 0; j < nby; ++j)
      for (int i = 0; i < nbx; ++i) {
        const size_t c00 = size_t(j) * gw + size_t(i), c10 = c00 + 1, c01 = c00 + gw, c11 = c01 + 1;
        const int above = s.grid_above[c00] + s.grid_above[c10] + s.grid_above[c01] + s.grid_above[c11];
        const float nu = std::max(std::max(s.grid_nu[c00], s.grid_nu[c10]), std::max(s.grid_nu[c01], s.grid_nu[c11]));
        const bool exact = (above != 0 && above != 4) || nu > cos_near_sun;
        s.block_exact[size_t(j) * size_t(nbx) + size_t(i)] = exact ? 1 : 0;
        if (!exact) {
          const float cx = 0.5f * float(grid_pixel(x0, w, i) + grid_pixel(x0, w, i + 1));
          const float cy = 0.5f * float(grid_pixel(y0, h, j) + grid_pixel(y0, h, j + 1));
          set_direction(s.tested.size(), direction(cx, cy));
          s.tested.push_back(j * nbx + i);
        }
      }
    s.centre.resize(s.tested.size());
    sky_radiance_batch(f, s.tested.size(), s.dir_x.data(), s.dir_y.data(), s.dir_z.data(), s.centre.data());
    for (size_t k = 0; k < s.tested.size(); ++k) {
      const int j = s.tested[k] / nbx, i = s.tested[k] % nbx;
      const size_t c00 = size_t(j) * gw + size_t(i), c10 = c00 + 1, c01 = c00 + gw, c11 = c01 + 1;
      const glm::vec3& centre = s.centre[k];
      const glm::vec3 mean = 0.25f * (s.grid[c00] + s.grid[c10] + s.grid[c01] + s.grid[c11]);
      const glm::vec3 diff = glm::abs(centre - mean);
      const bool exact = !(diff.x <= kBlockTolerance * centre.x && diff.y <= kBlockTolerance * centre.y &&
                           diff.z <= kBlockTolerance * centre.z);
      s.block_exact[size_t(s.tested[k])] = exact ? 1 : 0;
    }
  };

  const AerialPerspectiveLut* ap = f.space ? nullptr : f.aerial_perspective.get();
  const float froxel_range = ap ? ap->range() : -1.0f;
  FroxelRow fr{};
  int fw = 1, fh = 1, fd = 1;
  const FroxelTexel* froxels = nullptr;
  if (ap) {
    const FroxelCamera& fc = ap->camera();
    fw = ap->luminance().width;
    fh = ap->luminance().height;
    fd = ap->luminance().depth;
    froxels = ap->packed().data();
    fr.x_scale = 0.5f * float(fw) / (fc.tan_half_fov * fc.aspect);
    fr.x_bias = 0.5f * float(fw) - 0.5f;
    fr.y_scale = -0.5f * float(fh) / fc.tan_half_fov;
    fr.y_bias = 0.5f * float(fh) - 0.5f;
    fr.inv_extent = 1.0f / ap->extent();
    fr.depth = float(fd);
    fr.max_slice = float(fd - 1);
    fr.inv_first_slice = 1.0f / ap->slice_distance(0);
    fr.max_x = float(fw - 1);
    fr.max_y = float(fh - 1);
  }

  for (int y = y0; y < y1; ++y) {
    const float sy = screen_y(float(y));
    const glm::vec3 base = cam.forward + sy * cam.up;
    const size_t row = buffers.index(x0, y);
    const float* depth = buffers.depth.data() + row;
    const float* distance = buffers.distance.data() + row;
    glm::vec3* color = buffers.color.data() + row;
    if (y + kPrefetchRows < y1) {
      // A later row of the tile is another stream for the hardware prefetcher, which does not
      // catch these short (256-byte) rows in time: start it now. (One row ahead, the first
      // pass over a row still stalled on its loads.)
      const size_t next = row + size_t(kPrefetchRows) * size_t(w);
      for (size_t k = 0; k < n; k += 16) {
        __builtin_prefetch(buffers.depth.data() + next + k);
        __builtin_prefetch(buffers.distance.data() + next + k);
      }
      const char* next_color = reinterpret_cast<const char*>(buffers.color.data() + next);
      for (size_t b = 0; b < n * sizeof(glm::vec3); b += 64) __builtin_prefetch(next_color + b, 1);
    }
    const int bj = (y - y0) / kBlock;
    const uint8_t* exact_blocks = s.block_exact.data() + size_t(bj) * size_t(nbx);
    // Split the row's pixels: sky (per pixel or interpolated), inside the froxel range, and the rest (marched).
    // A row of geometry all inside the froxel range (the common case) needs no split.
    size_t n_sky = 0, n_interp = 0, n_froxel = 0, n_other = 0;
    int row_sky = 0, n_special = 0;
    for (size_t k = 0; k < n; ++k) {
      row_sky += depth[k] == 0.0f;
      n_special += (depth[k] == 0.0f) | !(distance[k] <= froxel_range);
    }
    if (row_sky > 0 && !grid_ready) build_grid();
    const int* froxel_index = s.identity.data();
    const float* froxel_sx = s.sx.data();
    const float* froxel_distance = distance;
    // A row of sky only (the common case above the horizon) lists only its exact pixels:
    // the interpolated blocks are filled block by block below.
    const bool all_sky = size_t(row_sky) == n;
    if (n_special == 0) {
      n_froxel = n;
    } else if (all_sky) {
      for (size_t k = 0; k < n; ++k) {
        s.sky[n_sky] = int(k);
        n_sky += exact_blocks[k / kBlock] != 0 ? 1 : 0;
      }
      n_interp = n - n_sky;
    } else {
      for (size_t k = 0; k < n; ++k) {
        const bool sky = depth[k] == 0.0f;
        const bool exact = sky && exact_blocks[k / kBlock] != 0;
        const bool froxel = !sky && distance[k] <= froxel_range;
        s.sky[n_sky] = int(k);
        s.interp[n_interp] = int(k);
        s.froxel[n_froxel] = int(k);
        s.other[n_other] = int(k);
        n_sky += exact ? 1 : 0;
        n_interp += (sky && !exact) ? 1 : 0;
        n_froxel += froxel ? 1 : 0;
        n_other += (!sky && !froxel) ? 1 : 0;
      }
    }
    const float len0 = glm::dot(base, base), len1 = 2.0f * glm::dot(base, cam.right),
                len2 = glm::dot(cam.right, cam.right);

    if (n_interp > 0) {
      const int gy0 = grid_pixel(y0, h, bj), gy1 = grid_pixel(y0, h, bj + 1);
      const float wy = gy1 > gy0 ? float(y - gy0) / float(gy1 - gy0) : 0.0f;
      // The grid row interpolated to this row, then each pixel between its two grid columns.
      const glm::vec3* g0 = s.grid.data() + size_t(bj) * gw;
      const glm::vec3* g1 = g0 + gw;
      for (size_t i = 0; i < gw; ++i) s.edge[i] = g0[i] + (g1[i] - g0[i]) * wy;
      if (all_sky) {
        for (size_t bi = 0; bi < size_t(nbx); ++bi) {
          if (exact_blocks[bi] != 0) continue;
          const glm::vec3 left = s.edge[bi], step = s.edge[bi + 1] - s.edge[bi];
          const size_t end = std::min(n, (bi + 1) * size_t(kBlock));
          for (size_t k = bi * size_t(kBlock); k < end; ++k) color[k] = left + step * s.wx[k];
        }
      } else {
        for (size_t j = 0; j < n_interp; ++j) {
          const size_t k = size_t(s.interp[j]);
          const size_t bi = k / size_t(kBlock);
          color[k] = s.edge[bi] + (s.edge[bi + 1] - s.edge[bi]) * s.wx[k];
        }
      }
    }

    if (n_sky > 0) {      sr.up = RowDot(f.up, base, cam.right);
      sr.sun = RowDot(f.sun, base, cam.right);
      sr.sun_h = RowDot(f.sun_horizontal, base, cam.right);
      sr.len0 = len0;
      sr.len1 = len1;
      sr.len2 = len2;
      for (size_t j = 0; j < n_sky; ++j) s.row_sx[j] = s.sx[size_t(s.sky[j])];
      float *fu = s.a.data(), *fv = s.b.data(), *ph = s.c.data(), *nu = s.d.data();
      if (mie_cornette_shanks)
        sky_coordinates(sr, [g](float c) { return cornette_shanks(c, g); }, n_sky, s.row_sx.data(), fu, fv,
                        ph, nu);
      else
        sky_coordinates(
            sr,
            [g, g2, lobe](float c) {
              return lobe * henyey_greenstein(c, g) + (1.0f - lobe) * henyey_greenstein(c, g2);
            },
            n_sky, s.row_sx.data(), fu, fv, ph, nu);
      for (size_t j = 0; j < n_sky; ++j) {
        const int u0 = int(fu[j]), v0 = int(fv[j]);
        const int du = u0 + 1 < sv_w ? 1 : 0;
        const size_t dv = v0 + 1 < sv_h ? size_t(sv_w) : 0;
        const Float4 wu = Float4{} + (fu[j] - float(u0)), wv = Float4{} + (fv[j] - float(v0));
        const SkyViewTexel* p = sky_texels + size_t(v0) * size_t(sv_w) + size_t(u0);
        auto bilinear = [&](size_t part) {
          const float* q = reinterpret_cast<const float*>(p) + part;
          const Float4 a = load4(q), b = load4(q + 8 * du);
          const Float4 c = load4(q + 8 * dv), d = load4(q + 8 * (dv + size_t(du)));
          const Float4 top = a + (b - a) * wu, bottom = c + (d - c) * wu;
          return top + (bottom - top) * wv;
        };
        Float4 l;
        if (f.fixed) {
          const SkyViewTexelQ15* pq = sky_q15 + size_t(v0) * size_t(sv_w) + size_t(u0);
          const fx::U16x8 b = bilinear_q15(pq, pq + du, pq + dv, pq + dv + size_t(du),
                                           splat_weight(fx::weight_q15(fu[j] - float(u0))),
                                           splat_weight(fx::weight_q15(fv[j] - float(v0))));
          Float4 rest, mie;
          decode_halves(b, rest_scale, mie_scale, rest, mie);
          l = (rest + mie * ph[j]) * e;
        } else {
          l = (bilinear(0) + bilinear(4) * ph[j]) * e;
        }
        const size_t k = size_t(s.sky[j]);
        glm::vec3 out(l[0], l[1], l[2]);
        if (nu[j] > f.cos_sun_radius) {  // the sun disk: a handful of pixels
          const float sx = s.sx[k];
          const glm::vec3 dir = glm::normalize(base + sx * cam.right);
          const float mu = glm::dot(dir, f.up);
          if (mu > f.mu_horizon) out += sun_disk_radiance(f, dir) * f.transmittance->to_top(f.camera_row, mu);
        }
        color[k] = out;
      }
    }

    if (n_froxel > 0) {
      const FroxelCamera& fc = ap->camera();
      fr.fwd = RowDot(fc.forward, base, cam.right);
      fr.right = RowDot(fc.right, base, cam.right);
      fr.up = RowDot(fc.up, base, cam.right);
      if (n_special != 0) {
        for (size_t j = 0; j < n_froxel; ++j) {
          s.row_sx[j] = s.sx[size_t(s.froxel[j])];
          s.dist[j] = distance[s.froxel[j]];
        }
        froxel_index = s.froxel.data();
        froxel_sx = s.row_sx.data();
        froxel_distance = s.dist.data();
      }
      if (f.fixed)
        apply_froxels_fixed(fr, FroxelVolumeQ15{ap->packed_q15().data(), fw, fh, ap->luminance_scale().scale},
                            n_froxel, froxel_index, froxel_sx, froxel_distance, s, e, color);
      else
        apply_froxels(fr, FroxelVolume{froxels, fw, fh}, n_froxel, froxel_index, froxel_sx, froxel_distance, s, e,
                      color);
    }

    for (size_t j = 0; j < n_other; ++j) {
      const size_t k = size_t(s.other[j]);
      const glm::vec3 dir = glm::normalize(base + s.sx[k] * cam.right);
      color[k] = apply_aerial_perspective(f, dir, distance[k], color[k]);
    }
  }
}

void composite_sky_fragments(const SkyFrame& f, int width, int height, std::span<EdgeFragment> fragments) {
  if (!f.valid) return;
  const PixelRays rays(f.camera, width, height);
  for (EdgeFragment& e : fragments) {
    const glm::vec3 dir = rays.direction(e.x, e.y);
    e.color = e.depth == 0.0f ? sky_radiance(f, dir, true) : apply_aerial_perspective(f, dir, e.distance, e.color);
  }
}

}  // namespace cr

#include "atmosphere/sky_composite.h"

#include <algorithm>
#include <cmath>

#include "atmosphere/fast_math.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"

namespace cr {

namespace {

// Per-pixel ray march (space fallback, and geometry beyond the AP range).
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
  return f.skyview->sample(f.skyview->mapping().to_unit(cos_vz, cos_lon), mie_phase(f.model, nu));
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

bool same_camera(const FroxelCamera& a, const Camera& c, const glm::dvec3& planet_position) {
  return a.position == planet_position && a.forward == c.forward && a.up == c.up && a.right == c.right &&
         a.tan_half_fov == std::tan(0.5f * c.vfov_rad) && a.aspect == c.aspect;
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

// Constants of one row of the composite's coordinate loop.
struct RowConstants {
  glm::vec3 base, right, up, sun_horizontal, sun;
  float zha, inv_zha, inv_beta, u_scale, v_scale;
};

// Directions and sky-view texel coordinates of a row of pixels: branch-free,
// restrict pointers and locals only, so it vectorizes (SkyViewMapping::to_unit inlined).
void row_coordinates(const RowConstants c, size_t n, const float* __restrict sx, float* __restrict dx,
                     float* __restrict dy, float* __restrict dz, float* __restrict sun_cos, float* __restrict fu,
                     float* __restrict fv) {
  for (size_t k = 0; k < n; ++k) {
    const float ux = c.base.x + sx[k] * c.right.x;
    const float uy = c.base.y + sx[k] * c.right.y;
    const float uz = c.base.z + sx[k] * c.right.z;
    const float inv_len = 1.0f / std::sqrt(ux * ux + uy * uy + uz * uz);
    const float ex = ux * inv_len, ey = uy * inv_len, ez = uz * inv_len;
    dx[k] = ex;
    dy[k] = ey;
    dz[k] = ez;
    sun_cos[k] = ex * c.sun.x + ey * c.sun.y + ez * c.sun.z;
    float cos_vz = ex * c.up.x + ey * c.up.y + ez * c.up.z;
    cos_vz = cos_vz < -1.0f ? -1.0f : (cos_vz > 1.0f ? 1.0f : cos_vz);
    const float sin_vz = std::sqrt(1.0f - cos_vz * cos_vz);
    const float along = ex * c.sun_horizontal.x + ey * c.sun_horizontal.y + ez * c.sun_horizontal.z;
    const float cos_lon = sin_vz > 1e-6f ? along / (sin_vz > 1e-6f ? sin_vz : 1.0f) : 1.0f;
    const float angle = fast_acos(cos_vz);
    const float above = 1.0f - angle * c.inv_zha;
    const float below = (angle - c.zha) * c.inv_beta;
    const float v = angle < c.zha ? 0.5f - 0.5f * std::sqrt(above > 0.0f ? above : 0.0f)
                                  : 0.5f + 0.5f * std::sqrt(below < 1.0f ? below : 1.0f);
    float uu = 0.5f - 0.5f * cos_lon;
    uu = uu < 0.0f ? 0.0f : (uu > 1.0f ? 1.0f : uu);
    fu[k] = std::sqrt(uu) * c.u_scale;
    fv[k] = v * c.v_scale;
  }
}

// The Mie phase of a row of view/sun cosines (a loop that vectorizes).
void mie_phases(const AtmosphereModel& m, size_t n, const float* __restrict nu, float* __restrict out) {
  for (size_t k = 0; k < n; ++k) out[k] = mie_phase(m, nu[k]);
}

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
  glm::vec3 l;
  const float mu = glm::dot(dir, f.up);
  if (f.space) {
    l = march_pixel(f, dir, 1e30).luminance * f.sun_illuminance;
  } else {
    l = skyview_lookup(f, dir) * f.sun_illuminance;
  }
  if (with_sun_disk && mu > f.mu_horizon) {
    const glm::vec3 disk = sun_disk_radiance(f, dir);
    if (disk != glm::vec3(0.0f)) l += disk * f.transmittance->to_top(f.camera_row, mu);
  }
  return l;
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
  FroxelSample s = sample_froxels(ap, lut_coord(fx, ap.luminance().width), lut_coord(fy, ap.luminance().height),
                                  std::min(froxel_distance, range));
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
  // Per-row work is split in two loops: a branch-free one over the row's pixels
  // computing directions and sky-view coordinates (it vectorizes), and a
  // per-pixel one doing the table fetches.
  thread_local std::vector<float> sx, dx, dy, dz, fu, fv, sun_cos, phase;
  for (auto* v : {&sx, &dx, &dy, &dz, &fu, &fv, &sun_cos, &phase}) v->resize(n);
  for (size_t k = 0; k < n; ++k) sx[k] = (2.0f * (float(x0 + int(k)) + 0.5f) / float(w) - 1.0f) * t * cam.aspect;

  const AerialPerspectiveLut* ap = f.space ? nullptr : f.aerial_perspective.get();
  const bool direct_froxels = ap && same_camera(ap->camera(), cam, f.camera_position);
  const float froxel_range = ap ? ap->range() : 0.0f;
  thread_local std::vector<LutCoord> columns;
  columns.resize(n);
  const int froxel_w = ap ? ap->luminance().width : 1;
  const int froxel_d = ap ? ap->luminance().depth : 1;
  if (ap)
    for (size_t k = 0; k < n; ++k)
      columns[k] = lut_coord((float(x0 + int(k)) + 0.5f) * float(froxel_w) / float(w) - 0.5f, froxel_w);
  const float fy_scale = ap ? float(ap->luminance().height) / float(h) : 0.0f;
  const size_t slice_stride = ap ? size_t(froxel_w) * size_t(ap->luminance().height) : 0;
  const glm::vec3* lum = ap ? ap->luminance().texels.data() : nullptr;
  const glm::vec3* trans = ap ? ap->transmittance().texels.data() : nullptr;
  const float froxel_depth = float(froxel_d);
  const float max_slice = float(froxel_d - 1);
  // slice_coordinate(d) = sqrt(d / extent) * depth - 0.5, with the division hoisted.
  const float inv_froxel_total = ap ? 1.0f / ap->extent() : 0.0f;
  const float first_slice = ap ? ap->slice_distance(0) : 0.0f;

  const SkyViewLut* sv = f.space ? nullptr : f.skyview.get();
  const float zha = sv ? sv->mapping().zenith_horizon_angle : 1.0f;
  const float inv_zha = 1.0f / zha;
  const float inv_beta = sv ? 1.0f / sv->mapping().beta : 1.0f;
  const float u_scale = sv ? float(sv->image().width - 1) : 0.0f;
  const float v_scale = sv ? float(sv->image().height - 1) : 0.0f;
  const glm::vec3 up = f.up, sh = f.sun_horizontal, sun = f.sun;

  RowConstants rc;
  rc.right = cam.right;
  rc.up = up;
  rc.sun_horizontal = sh;
  rc.sun = sun;
  rc.zha = zha;
  rc.inv_zha = inv_zha;
  rc.inv_beta = inv_beta;
  rc.u_scale = u_scale;
  rc.v_scale = v_scale;
  for (int y = y0; y < y1; ++y) {
    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(h)) * t;
    rc.base = cam.forward + sy * cam.up;
    // Directions are only needed for sky pixels and off the direct froxel path.
    bool needs_directions = !direct_froxels;
    for (int x = x0; x < x1 && !needs_directions; ++x) {
      const size_t i = buffers.index(x, y);
      needs_directions = buffers.depth[i] == 0.0f || buffers.distance[i] > froxel_range;
    }
    if (needs_directions) {
      row_coordinates(rc, n, sx.data(), dx.data(), dy.data(), dz.data(), sun_cos.data(), fu.data(), fv.data());
      if (sv) mie_phases(f.model, n, sun_cos.data(), phase.data());
    }
    const LutCoord fy = lut_coord((float(y) + 0.5f) * fy_scale - 0.5f, ap ? ap->luminance().height : 1);
    const size_t row0 = size_t(fy.i0) * size_t(froxel_w), row1 = size_t(fy.i1) * size_t(froxel_w);
    for (size_t k = 0; k < n; ++k) {
      const int x = x0 + int(k);
      const size_t i = buffers.index(x, y);
      glm::vec3& c = buffers.color[i];
      if (buffers.depth[i] == 0.0f) {
        if (sv) {
          const LutCoord cu = lut_coord(fu[k], sv->image().width), cv = lut_coord(fv[k], sv->image().height);
          c = (sample_bilinear(sv->image(), cu, cv) + sample_bilinear(sv->mie_image(), cu, cv) * phase[k]) *
              f.sun_illuminance;
          if (sun_cos[k] > f.cos_sun_radius) {
            const glm::vec3 dir(dx[k], dy[k], dz[k]);
            const float mu = glm::dot(dir, up);
            if (mu > f.mu_horizon) c += sun_disk_radiance(f, dir) * f.transmittance->to_top(f.camera_row, mu);
          }
        } else {
          c = sky_radiance(f, glm::vec3(dx[k], dy[k], dz[k]), true);
        }
        continue;
      }
      const float d = buffers.distance[i];
      if (direct_froxels && d <= froxel_range) {
        // Trilinear froxel fetch with the column and row weights of this tile/row.
        float sz = std::sqrt(d * inv_froxel_total) * froxel_depth - 0.5f;
        sz = sz < max_slice ? (sz > 0.0f ? sz : 0.0f) : max_slice;
        const int z0 = int(sz);
        const int z1 = z0 + 1 < froxel_d ? z0 + 1 : z0;
        const float wz = sz - float(z0);
        const LutCoord& cx = columns[k];
        auto fetch = [&](const glm::vec3* img, int z) {
          const glm::vec3* p = img + size_t(z) * slice_stride;
          const glm::vec3 a = p[row0 + size_t(cx.i0)] + (p[row0 + size_t(cx.i1)] - p[row0 + size_t(cx.i0)]) * cx.w;
          const glm::vec3 b = p[row1 + size_t(cx.i0)] + (p[row1 + size_t(cx.i1)] - p[row1 + size_t(cx.i0)]) * cx.w;
          return a + (b - a) * fy.w;
        };
        const glm::vec3 l0 = fetch(lum, z0), t0 = fetch(trans, z0);
        if (d < first_slice) {  // between the camera (T = 1, nothing scattered) and the first slice
          const float wd = d / first_slice;
          c = c * (glm::vec3(1.0f) + (t0 - glm::vec3(1.0f)) * wd) + l0 * wd * f.sun_illuminance;
          continue;
        }
        const glm::vec3 l = l0 + (fetch(lum, z1) - l0) * wz;
        const glm::vec3 tr = t0 + (fetch(trans, z1) - t0) * wz;
        c = c * tr + l * f.sun_illuminance;
      } else {
        c = apply_aerial_perspective(f, glm::vec3(dx[k], dy[k], dz[k]), d, c);
      }
    }
  }
}

}  // namespace cr

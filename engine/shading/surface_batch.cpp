#include "engine/core/half_rounding.h"
#include "engine/shading/surface_batch.h"

#include <cmath>

#include "engine/shading/safe_normalize.h"
#include "engine/raster/triangle_interp.h"
#include "engine/shading/surface.h"

namespace cr {
namespace {

// Out of line so that each stays a vectorised loop (inlined, GCC loses track
// of the batch's arrays). Same float operations, in the same order, as
// TriangleSurface::at with glm (dot = (x x + y y) + z z).

// normalize_or(n, geometric normal) per point.
[[gnu::noinline]] void unit_normals(SurfaceBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    const float x = s.nx[i], y = s.ny[i], z = s.nz[i];
    const float fx = s.fx[i], fy = s.fy[i], fz = s.fz[i];
    const float len = std::sqrt(x * x + y * y + z * z);
    const bool ok = usable_length(len);
    s.nx[i] = ok ? x / len : fx;
    s.ny[i] = ok ? y / len : fy;
    s.nz[i] = ok ? z / len : fz;
  }
}

// Gram-Schmidt of the tangent against the unit normal, falling back to
// orthogonal_tangent(n) where nothing of the tangent is left.
[[gnu::noinline]] void tangent_frames(SurfaceBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    const float nx = s.nx[i], ny = s.ny[i], nz = s.nz[i];
    const float d = nx * s.tx[i] + ny * s.ty[i] + nz * s.tz[i];
    const float x = s.tx[i] - nx * d, y = s.ty[i] - ny * d, z = s.tz[i] - nz * d;
    const float len = std::sqrt(x * x + y * y + z * z);
    const bool ok = usable_length(len);
    const float sign = std::copysign(1.0f, nz);
    const float a = -1.0f / (sign + nz);
    const float b = nx * ny * a;
    s.tx[i] = ok ? x / len : 1.0f + sign * nx * nx * a;
    s.ty[i] = ok ? y / len : sign * b;
    s.tz[i] = ok ? z / len : -sign * nx;
  }
}

// Back faces turn the whole frame (N, T and the bitangent sign) around.
[[gnu::noinline]] void face_normals(SurfaceBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    s.nx[i] *= s.facing[i];
    s.ny[i] *= s.facing[i];
    s.nz[i] *= s.facing[i];
  }
}

[[gnu::noinline]] void face_tangents(SurfaceBatch& s) {
  for (int i = 0; i < s.count; ++i) {
    s.tx[i] *= s.facing[i];
    s.ty[i] *= s.facing[i];
    s.tz[i] *= s.facing[i];
    s.tw[i] *= s.facing[i];
  }
}

// out[k] = (w0[k] v0 + w1[k] v1) + w2[k] v2: at()'s glm interpolation of one
// component, or `absent` for every point where the stream is missing.
[[gnu::always_inline]] inline void lerp(const float* w0, const float* w1, const float* w2, float v0, float v1,
                                        float v2, bool present, float absent, int count, float* out) {
  if (!present) {
    for (int k = 0; k < count; ++k) out[k] = absent;
    return;
  }
  for (int k = 0; k < count; ++k) out[k] = w0[k] * v0 + w1[k] * v1 + w2[k] * v2;
}

}  // namespace

void TriangleSurface::add_span(SurfaceBatch& batch, const TriangleInterp& interp, int x0, int count, int y) const {
  float px[SurfaceBatch::kCapacity], py[SurfaceBatch::kCapacity];
  for (int k = 0; k < count; ++k) {
    px[k] = float(x0 + k) + 0.5f;
    py[k] = float(y) + 0.5f;
  }
  add_points(batch, interp, px, py, count);
}

void TriangleSurface::add_points(SurfaceBatch& batch, const TriangleInterp& interp, const float* px, const float* py,
                                 int count) const {
  // Barycentrics and their derivatives per point: interpolate() of
  // triangle_interp.h, in locals (stores into the batch could otherwise
  // alias the planes, and the loop would not vectorise).
  constexpr int kN = SurfaceBatch::kCapacity;
  float w[3][kN], wx[3][kN], wy[3][kN];
  {
    const float u0[3] = {interp.u0[0], interp.u0[1], interp.u0[2]};
    const float ux[3] = {interp.ux[0], interp.ux[1], interp.ux[2]};
    const float uy[3] = {interp.uy[0], interp.uy[1], interp.uy[2]};
    const float ref_x = interp.ref_x, ref_y = interp.ref_y;
    const float sx = ux[0] + ux[1] + ux[2];
    const float sy = uy[0] + uy[1] + uy[2];
    for (int k = 0; k < count; ++k) {
      const float dx = px[k] - ref_x, dy = py[k] - ref_y;
      const float a0 = u0[0] + (ux[0] * dx + uy[0] * dy);
      const float a1 = u0[1] + (ux[1] * dx + uy[1] * dy);
      const float a2 = u0[2] + (ux[2] * dx + uy[2] * dy);
      const float inv = 1.0f / (a0 + a1 + a2);
      const float b0 = a0 * inv, b1 = a1 * inv, b2 = a2 * inv;
      w[0][k] = b0;
      w[1][k] = b1;
      w[2][k] = b2;
      wx[0][k] = (ux[0] - b0 * sx) * inv;
      wx[1][k] = (ux[1] - b1 * sx) * inv;
      wx[2][k] = (ux[2] - b2 * sx) * inv;
      wy[0][k] = (uy[0] - b0 * sy) * inv;
      wy[1][k] = (uy[1] - b1 * sy) * inv;
      wy[2][k] = (uy[2] - b2 * sy) * inv;
    }
  }
  // at()'s interpolations; absent streams take at()'s defaults, and a zero
  // normal falls back to the geometric one when the batch is finished.
  const int i = batch.count;
  auto attribute = [&](const float (&weights)[3][kN], int c, const auto& v, bool present, float absent, float* out)
      __attribute__((always_inline)) {
    lerp(weights[0], weights[1], weights[2], v[0][c], v[1][c], v[2][c], present, absent, count, out + i);
  };
  for (int c = 0; c < 3; ++c) {
    attribute(w, c, position_, true, 0.0f, c == 0 ? batch.px : c == 1 ? batch.py : batch.pz);
    attribute(w, c, normal_, has_normals_, 0.0f, c == 0 ? batch.nx : c == 1 ? batch.ny : batch.nz);
    attribute(w, c, tangent_, has_tangents_ && with_tangent_, 0.0f, c == 0 ? batch.tx : c == 1 ? batch.ty : batch.tz);
  }
  attribute(w, 0, uv_, has_uv_, 0.0f, batch.u);
  attribute(w, 1, uv_, has_uv_, 0.0f, batch.v);
  attribute(wx, 0, uv_, has_uv_, 0.0f, batch.du_dx);
  attribute(wx, 1, uv_, has_uv_, 0.0f, batch.dv_dx);
  attribute(wy, 0, uv_, has_uv_, 0.0f, batch.du_dy);
  attribute(wy, 1, uv_, has_uv_, 0.0f, batch.dv_dy);
  if (with_uv1_) {
    attribute(w, 0, uv1_, has_uv1_, 0.0f, batch.u1);
    attribute(w, 1, uv1_, has_uv1_, 0.0f, batch.v1);
    attribute(wx, 0, uv1_, has_uv1_, 0.0f, batch.du1_dx);
    attribute(wx, 1, uv1_, has_uv1_, 0.0f, batch.dv1_dx);
    attribute(wy, 0, uv1_, has_uv1_, 0.0f, batch.du1_dy);
    attribute(wy, 1, uv1_, has_uv1_, 0.0f, batch.dv1_dy);
  }
  attribute(w, 0, color_, has_color_, 1.0f, batch.cr);
  attribute(w, 1, color_, has_color_, 1.0f, batch.cg);
  attribute(w, 2, color_, has_color_, 1.0f, batch.cb);
  attribute(w, 3, color_, has_color_, 1.0f, batch.ca);
  if (half_attributes_) {  // fp16 varyings, as at() rounds them (absent streams' defaults are halves already)
    for (float* a : {batch.nx, batch.ny, batch.nz, batch.tx, batch.ty, batch.tz, batch.u, batch.v, batch.cr, batch.cg,
                     batch.cb, batch.ca})
      for (int k = i; k < i + count; ++k) a[k] = round_to_half(a[k]);
    if (with_uv1_)
      for (float* a : {batch.u1, batch.v1})
        for (int k = i; k < i + count; ++k) a[k] = round_to_half(a[k]);
  }
  const float tw = with_tangent_ ? bitangent_sign_ : 1.0f;
  const float facing = front_facing_ ? 1.0f : -1.0f;
  const glm::vec3 f = geometric_normal_;
  for (int k = i; k < i + count; ++k) {
    batch.fx[k] = f.x;
    batch.fy[k] = f.y;
    batch.fz[k] = f.z;
    batch.tw[k] = tw;
    batch.facing[k] = facing;
  }
  batch.count = i + count;
  batch.any_tangent |= with_tangent_;
}

void SurfaceBatch::finish() {
  unit_normals(*this);
  if (any_tangent) {
    tangent_frames(*this);
    face_tangents(*this);
  }
  face_normals(*this);
}

}  // namespace cr

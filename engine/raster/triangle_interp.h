#pragma once
// Perspective-correct interpolation over an ORIGINAL (unclipped) triangle.
//
// With the clip-space vertices c0, c1, c2 as columns (x, y, w) of a matrix M,
// u = M^-1 (ndc_x, ndc_y, 1) is affine in screen space (homogeneous
// rasterisation, Olano & Greer 1997), and the perspective-correct barycentrics
// are b_i = u_i / (u0 + u1 + u2); sum(u) = 1/w of the visible point and
// sum(u_i z_i) is its NDC depth. Because the planes come from the original
// vertices, every piece the clipper cuts from one triangle interpolates with
// the very same function (no seams along clip edges), vertices behind the eye
// need no special case, and derivatives follow exactly from the quotient rule,
// also at pixels outside the triangle.
#include <cstdint>

#include "engine/raster/barycentrics.h"

namespace cr {

struct TriangleInterp {
  // u_i(px, py) = u0[i] + (ux[i] * (px - ref_x) + uy[i] * (py - ref_y)), px/py in pixels.
  float u0[3];
  float ux[3];
  float uy[3];
  float ref_x;  // a pixel centre near the triangle, so the plane terms stay small
  float ref_y;
  uint32_t draw_index;
  uint32_t triangle_index;
  bool front_facing;
};

// Barycentrics and their per-pixel derivatives at screen position (px, py);
// the centre of pixel (x, y) is (x + 0.5, y + 0.5).
inline Barycentrics interpolate(const TriangleInterp& t, float px, float py) {
  const float dx = px - t.ref_x, dy = py - t.ref_y;
  float u[3];
  for (int i = 0; i < 3; ++i) u[i] = t.u0[i] + (t.ux[i] * dx + t.uy[i] * dy);
  const float s = u[0] + u[1] + u[2];
  const float sx = t.ux[0] + t.ux[1] + t.ux[2];
  const float sy = t.uy[0] + t.uy[1] + t.uy[2];
  const float inv = 1.0f / s;
  Barycentrics r;
  for (int i = 0; i < 3; ++i) {
    r.b[i] = u[i] * inv;
    // d(u/s) = (du - (u/s) ds) / s
    r.ddx[i] = (t.ux[i] - r.b[i] * sx) * inv;
    r.ddy[i] = (t.uy[i] - r.b[i] * sy) * inv;
  }
  return r;
}

}  // namespace cr

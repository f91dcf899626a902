#pragma once
// The surfaces of a batch of shading points, structure-of-arrays. Points are
// added with plain interpolations (TriangleSurface::add_span: multiplies and
// adds, a vectorised loop over a run of pixels); finish() then does what TriangleSurface::at does past them (the
// unit normal, the Gram-Schmidt tangent, the back-face flip) in vectorised
// loops over the batch, so the square roots and divides that a point waited
// on run four points at a time. After finish(), point k holds the floats of
// at() for the same triangle and barycentrics (tested bit for bit).
#include <glm/glm.hpp>

namespace cr {

struct SurfaceBatch {
  static constexpr int kCapacity = 64;

  int count = 0;
  float px[kCapacity], py[kCapacity], pz[kCapacity];  // position, world space
  // The interpolated normal (zero for primitives without normals); unit and
  // towards the viewer's side after finish().
  float nx[kCapacity], ny[kCapacity], nz[kCapacity];
  // The triangle's geometric normal: stands in for missing or degenerate normals.
  float fx[kCapacity], fy[kCapacity], fz[kCapacity];
  // The interpolated tangent and the bitangent sign; after finish(), the unit
  // tangent orthogonal to the normal, frame flipped for back faces. Read only
  // for points added with a tangent (TriangleSurface's with_tangent).
  float tx[kCapacity], ty[kCapacity], tz[kCapacity], tw[kCapacity];
  float u[kCapacity], v[kCapacity];                // TEXCOORD_0
  float du_dx[kCapacity], dv_dx[kCapacity];        // UV change per pixel step in x
  float du_dy[kCapacity], dv_dy[kCapacity];        // ... and in y
  // TEXCOORD_1 and its derivatives: read only for points added with it
  // (TriangleSurface's with_uv1).
  float u1[kCapacity], v1[kCapacity];
  float du1_dx[kCapacity], dv1_dx[kCapacity];
  float du1_dy[kCapacity], dv1_dy[kCapacity];
  float cr[kCapacity], cg[kCapacity], cb[kCapacity], ca[kCapacity];  // COLOR_0, linear RGBA
  float facing[kCapacity];  // +1 for a front face, -1 for a back face
  bool any_tangent = false;  // whether some point was added with a tangent

  bool full() const { return count == kCapacity; }
  void clear() {
    count = 0;
    any_tangent = false;
  }
  // Normals, tangents and back faces of every point, as TriangleSurface::at.
  void finish();
};

}  // namespace cr

#pragma once
// KHR_texture_transform applied to texture coordinates: uv' = T * R * S * uv,
// that is offset + R(rotation) * (scale * uv) with
//   R = | cos  sin |
//       |-sin  cos |
// (row-major): the extension's rotation "counter-clockwise in UV space",
// whose V axis points down. The GLSL listing of the extension reads as the
// opposite turn once its column-major mat3 is expanded; implementations and
// its sample model (TextureTransformTest: the arrow must point at the green
// marker, the red one marks the reversed turn) agree on this one
// (KhronosGroup/glTF#1563, #1624).
#include <glm/glm.hpp>

#include "engine/scene/scene.h"
#include "engine/shading/texture_sampler.h"

namespace cr {

// The transform as an affine map: u' = (m00 u + m01 v) + t0, v' = (m10 u + m11 v) + t1.
// Trivial (no default values): shading sets many up per frame, most unused.
struct UvAffine {
  float m00, m01, m10, m11;
  float t0, t1;
};
UvAffine uv_affine(const UvTransform& transform);

// Whether two texture references read their images through the same transform.
inline bool same_transform(const UvTransform& a, const UvTransform& b) {
  return a.offset == b.offset && a.rotation == b.rotation && a.scale == b.scale;
}

// Storage for transformed texture coordinates of a batch of points.
struct TransformedUvs {
  float u[TexturePoints::kCapacity], v[TexturePoints::kCapacity];
  float du_dx[TexturePoints::kCapacity], dv_dx[TexturePoints::kCapacity];
  float du_dy[TexturePoints::kCapacity], dv_dy[TexturePoints::kCapacity];
};

// The points with their coordinates mapped by `a` into `storage`: UVs by the
// whole map, UV derivatives by its linear part (so that the level of detail
// follows the scale). Returns the points over `storage`.
TexturePoints transform_uvs(const UvAffine& a, const TexturePoints& points, TransformedUvs& storage);

// A normal map read through a transformed UV set stores its normals in the
// tangent frame of the transformed coordinates (tangent along +u', bitangent
// towards -v', glTF's convention), while the surface's tangent frame follows
// the untransformed ones. Row-major 2x2 taking the map's tangent-space XY to
// the surface frame's: the linear part's inverse with unit columns (only the
// turn and mirroring matter: a frame's vectors are unit). Identity for an
// untransformed set. Trivial, as UvAffine.
struct NormalMapTurn {
  float xx, xy, yx, yy;
};
NormalMapTurn normal_map_turn(const UvAffine& a);
inline float turned_x(const NormalMapTurn& r, float x, float y) { return r.xx * x + r.xy * y; }
inline float turned_y(const NormalMapTurn& r, float x, float y) { return r.yx * x + r.yy * y; }

}  // namespace cr

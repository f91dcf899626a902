#pragma once
// The surface seen by a pixel: the original triangle's vertex attributes,
// interpolated with the rasterizer's perspective-correct barycentrics and
// placed in world space.
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/raster/barycentrics.h"
#include "engine/scene/scene.h"

namespace cr {

struct SurfaceBatch;    // surface_batch.h
struct TriangleInterp;  // engine/raster/triangle_interp.h

struct SurfaceSample {
  glm::vec3 position{0.0f};               // world space
  glm::vec3 normal{0.0f, 1.0f, 0.0f};     // unit, world space, towards the viewer's side for back faces
  glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};  // unit xyz orthogonal to normal; w = bitangent sign
  glm::vec2 uv{0.0f};                     // TEXCOORD_0
  glm::vec2 duv_dx{0.0f};                 // UV change per pixel step in x
  glm::vec2 duv_dy{0.0f};                 // ... and in y
  // TEXCOORD_1 and its derivatives: interpolated only with_uv1 (for
  // materials whose textures read it, needs_uv1 of material_eval.h).
  glm::vec2 uv1{0.0f}, duv1_dx{0.0f}, duv1_dy{0.0f};
  glm::vec4 color{1.0f};                  // COLOR_0, linear RGBA
  bool front_facing = true;
};

// One triangle of `primitive` placed by `draw`, its vertex attributes moved
// to world space once: positions by Draw::world, normals by
// Draw::normal_matrix, tangents by the world 3x3 (bitangent sign flipped for
// mirrored draws). Pixels covered by the same triangle interpolate from it
// without re-fetching and re-transforming the vertices. Missing streams
// default to uv 0, colour 1 and an arbitrary tangent orthogonal to the
// normal. A back face flips the normal and tangent frame: the rasterizer
// culls back faces of single-sided materials (glTF), so a back face here
// belongs to a double-sided one. with_tangent = false skips the tangent frame
// (SurfaceSample::tangent keeps its default) for materials without a normal
// map, the only reader of it; with_uv1 = true adds TEXCOORD_1 (uv 0 where the
// primitive has none) for materials whose textures read it.
class TriangleSurface {
 public:
  // half_attributes: the interpolated normal, tangent, UVs and colour are
  // rounded to fp16 (round_to_half), as a phone's mediump varyings are; the
  // position and the UV derivatives stay float (profile "precision":
  // {"attributes": "float16"}).
  TriangleSurface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index, bool front_facing,
                  bool with_tangent = true, bool with_uv1 = false, bool half_attributes = false);
  // The surface at barycentrics `bary`; UV derivatives from its derivatives.
  SurfaceSample at(const Barycentrics& bary) const;
  // Appends the surfaces at the centres of pixels x0 .. x0 + count - 1 of
  // row y, barycentrics from `interp` (the triangle's planes), to the batch
  // (which must have room): interpolated but not yet made unit, so that
  // once the batch is finished point k holds the floats of
  // at(interpolate(interp, float(x0 + k) + 0.5f, float(y) + 0.5f)).
  void add_span(SurfaceBatch& batch, const TriangleInterp& interp, int x0, int count, int y) const;
  // The same at screen positions (px[k], py[k]) (pixels), k < count.
  void add_points(SurfaceBatch& batch, const TriangleInterp& interp, const float* px, const float* py,
                  int count) const;

 private:
  glm::vec3 position_[3];
  glm::vec3 normal_[3];      // world, not normalised (interpolated, then normalised)
  glm::vec3 geometric_normal_;  // backs up missing or degenerate shading normals
  glm::vec3 tangent_[3];     // world 3x3 * tangent xyz
  glm::vec2 uv_[3];
  glm::vec2 uv1_[3];  // set only with_uv1
  glm::vec4 color_[3];
  float bitangent_sign_ = 1.0f;
  bool has_normals_, has_tangents_, has_uv_, has_uv1_, has_color_, with_tangent_, with_uv1_, front_facing_,
      half_attributes_;
};

// TriangleSurface(primitive, draw, triangle_index, front_facing, with_tangent, with_uv1).at(bary).
SurfaceSample interpolate_surface(const Primitive& primitive, const Draw& draw, uint32_t triangle_index,
                                  const Barycentrics& bary, bool front_facing, bool with_tangent = true,
                                  bool with_uv1 = false);

// Only the UVs (with derivatives; TEXCOORD_1 too with_uv1) and colour of a
// triangle at `bary`, the rest of the sample at its defaults: what alpha
// coverage (material_alpha) reads, for the rasterizer's per-fragment MASK test.
SurfaceSample interpolate_uv_color(const Primitive& primitive, uint32_t triangle_index, const Barycentrics& bary,
                                   bool with_uv1 = false);

// A unit tangent orthogonal to unit n, continuous except where n.z changes
// sign (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
glm::vec3 orthogonal_tangent(const glm::vec3& n);

}  // namespace cr

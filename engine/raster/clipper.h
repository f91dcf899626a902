#pragma once
// Homogeneous clipping of a triangle against the planes that keep its screen
// projection finite and its fixed-point coordinates in range:
//   near   w - z >= 0   (NDC z <= 1; for the reversed-Z perspective z = znear, so w >= znear > 0)
//   far    z >= 0       (NDC z >= 0; never clips the infinite perspective, bounds an ortho range)
//   guard  |x| <= gx w, |y| <= gy w   (a guard band well beyond the image, not the image edges:
//                                       pixels outside the image are rejected by the bounding box)
// Done in double on the float clip positions. Intersections are always computed
// from the inside vertex towards the outside one, so an edge shared by two
// triangles is cut at bit-identical points and the mesh stays watertight.
#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace cr {

struct GuardBand {
  double gx = 1.0;  // clip |x| <= gx * w
  double gy = 1.0;
  // The band for a width x height image with `margin_pixels` beyond each edge.
  static GuardBand for_image(int width, int height, int margin_pixels);
};

inline constexpr int kClipPlaneCount = 6;
inline constexpr int kMaxClippedVertices = 3 + kClipPlaneCount;  // each plane adds at most one

struct ClipPolygon {
  std::array<glm::dvec4, kMaxClippedVertices> v;
  int count = 0;
};

// Bit p set when v is outside plane p.
uint32_t clip_outcode(const glm::dvec4& v, const GuardBand& band);

// Clips the triangle against the planes in `planes` (a union of outcodes).
// The polygon keeps the triangle's winding; count < 3 means nothing is left.
void clip_triangle(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c, uint32_t planes,
                   const GuardBand& band, ClipPolygon& out);

}  // namespace cr

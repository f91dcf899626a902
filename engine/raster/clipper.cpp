#include "engine/raster/clipper.h"

namespace cr {

namespace {

double plane_distance(int plane, const glm::dvec4& v, const GuardBand& band) {
  switch (plane) {
    case 0: return v.w - v.z;
    case 1: return v.z;
    case 2: return band.gx * v.w - v.x;
    case 3: return band.gx * v.w + v.x;
    case 4: return band.gy * v.w - v.y;
    default: return band.gy * v.w + v.y;
  }
}

}  // namespace

GuardBand GuardBand::for_image(int width, int height, int margin_pixels) {
  // Pixel x = (ndc + 1) * width / 2, so ndc = -1 - 2m/width lies m pixels left of the image.
  return {1.0 + 2.0 * margin_pixels / width, 1.0 + 2.0 * margin_pixels / height};
}

uint32_t clip_outcode(const glm::dvec4& v, const GuardBand& band) {
  uint32_t code = 0;
  for (int p = 0; p < kClipPlaneCount; ++p)
    if (plane_distance(p, v, band) < 0.0) code |= 1u << p;
  return code;
}

void clip_triangle(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c, uint32_t planes,
                   const GuardBand& band, ClipPolygon& out) {
  ClipPolygon scratch;
  ClipPolygon* src = &out;
  ClipPolygon* dst = &scratch;
  out.v[0] = a;
  out.v[1] = b;
  out.v[2] = c;
  out.count = 3;
  for (int p = 0; p < kClipPlaneCount; ++p) {
    if (!(planes & (1u << p))) continue;
    dst->count = 0;
    const int n = src->count;
    for (int i = 0; i < n; ++i) {
      const glm::dvec4& cur = src->v[i];
      const glm::dvec4& next = src->v[(i + 1) % n];
      const double dc = plane_distance(p, cur, band);
      const double dn = plane_distance(p, next, band);
      const bool cur_in = dc >= 0.0, next_in = dn >= 0.0;
      if (cur_in) dst->v[dst->count++] = cur;
      if (cur_in != next_in) {
        // From the inside vertex, whichever way the polygon walks the edge.
        const glm::dvec4& in = cur_in ? cur : next;
        const glm::dvec4& outside = cur_in ? next : cur;
        const double din = cur_in ? dc : dn, dout = cur_in ? dn : dc;
        const double t = din / (din - dout);
        dst->v[dst->count++] = in + t * (outside - in);
      }
    }
    std::swap(src, dst);
    if (src->count < 3) break;
  }
  if (src != &out) out = *src;
}

}  // namespace cr

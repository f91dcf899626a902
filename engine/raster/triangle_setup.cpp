#include "engine/raster/triangle_setup.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace cr {

namespace {

bool finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Nearest integer, halves away from zero (inline: SSE2 has no rounding instruction).
int32_t round_to_int(double v) { return int32_t(v >= 0.0 ? v + 0.5 : v - 0.5); }

// Screen position in subpixels and NDC depth of a clip-space point with w > 0.
void snap(const glm::dvec4& q, const SetupParams& p, int32_t& x, int32_t& y, double& z) {
  const double inv_w = 1.0 / q.w;
  const double sx = (q.x * inv_w + 1.0) * (0.5 * p.width), sy = (1.0 - q.y * inv_w) * (0.5 * p.height);
  x = round_to_int(sx * kSubpixelScale);
  y = round_to_int(sy * kSubpixelScale);
  z = q.z * inv_w;
}

// Pixels whose centre lies within the subpixel range [lo, hi]: centre of
// pixel p is 256p + 128, so p >= ceil((lo - 128) / 256) and p <= floor((hi - 128) / 256).
int32_t first_pixel(int32_t lo) { return (lo + (kSubpixelScale / 2 - 1)) >> kSubpixelBits; }
int32_t last_pixel(int32_t hi) { return (hi - kSubpixelScale / 2) >> kSubpixelBits; }

// Pixels with a sample within [lo, hi] (samples up to p.sample_margin from the centre).
PixelRect pixel_bounds(const int32_t* xs, const int32_t* ys, int n, const SetupParams& p) {
  int32_t xmin = xs[0], xmax = xs[0], ymin = ys[0], ymax = ys[0];
  for (int i = 1; i < n; ++i) {
    xmin = std::min(xmin, xs[i]);
    xmax = std::max(xmax, xs[i]);
    ymin = std::min(ymin, ys[i]);
    ymax = std::max(ymax, ys[i]);
  }
  const int32_t m = p.sample_margin;
  return intersect({first_pixel(xmin - m), first_pixel(ymin - m), last_pixel(xmax + m), last_pixel(ymax + m)},
                   {0, 0, p.width - 1, p.height - 1});
}

// Edge from (xi, yi) to (xj, yj) of a triangle with positive area in pixel
// (y-down) coordinates, so the interior is where the edge function is positive.
void set_edge(ScreenTriangle& t, int e, int32_t xi, int32_t yi, int32_t xj, int32_t yj) {
  const int32_t a = yi - yj, b = xj - xi;
  // E(X, Y) = a X + b Y + c at subpixel position (X, Y).
  const int64_t c = -(int64_t(a) * xi + int64_t(b) * yi);
  // Top-left rule: samples exactly on an edge belong to the triangle only if
  // the edge is a left edge (interior to its right, a > 0) or a top edge
  // (horizontal with the interior below, a == 0 and b > 0).
  const bool top_left = a > 0 || (a == 0 && b > 0);
  // At the centre of pixel (x, y): E = 256 (a x + b y) + k with
  // k = 128 (a + b) + c. Covered iff E >= 0 (top-left) or E >= 1, and as
  // a x + b y is an integer this equals a x + b y + floor(k' / 256) >= 0.
  t.a[e] = a;
  t.b[e] = b;
  t.c_num[e] = int64_t(kSubpixelScale / 2) * (int64_t(a) + b) + c - (top_left ? 0 : 1);
}

// Covered pixel centres of a small triangle within r (at most kTinySize
// pixels either way), as ScreenTriangle::mask; the edge values fit in int32.
uint64_t tiny_coverage(const ScreenTriangle& t, const PixelRect& r) {
  __m128i f_lo[3], f_hi[3], step[3];
  for (int e = 0; e < 3; ++e) {
    const int32_t a = t.a[e];
    const __m128i f = _mm_set1_epi32(int32_t(t.c(e) + int64_t(a) * r.x0 + int64_t(t.b[e]) * r.y0));
    f_lo[e] = _mm_add_epi32(f, _mm_setr_epi32(0, a, 2 * a, 3 * a));
    f_hi[e] = _mm_add_epi32(f, _mm_setr_epi32(4 * a, 5 * a, 6 * a, 7 * a));
    step[e] = _mm_set1_epi32(t.b[e]);
  }
  const unsigned cols = (2u << (r.x1 - r.x0)) - 1;
  uint64_t mask = 0;
  for (int j = 0; j <= r.y1 - r.y0; ++j) {
    // Covered where no edge value is negative (sign bit of the OR clear).
    const __m128i lo = _mm_or_si128(_mm_or_si128(f_lo[0], f_lo[1]), f_lo[2]);
    const __m128i hi = _mm_or_si128(_mm_or_si128(f_hi[0], f_hi[1]), f_hi[2]);
    const unsigned outside =
        unsigned(_mm_movemask_ps(_mm_castsi128_ps(lo))) | unsigned(_mm_movemask_ps(_mm_castsi128_ps(hi))) << 4;
    mask |= uint64_t(~outside & cols) << (kTinySize * j);
    for (int e = 0; e < 3; ++e) {
      f_lo[e] = _mm_add_epi32(f_lo[e], step[e]);
      f_hi[e] = _mm_add_epi32(f_hi[e], step[e]);
    }
  }
  return mask;
}

}  // namespace

void SetupBatch::clear(uint32_t first_id) {
  id_base = first_id;
  interps.clear();
  triangles.clear();
  bounds.clear();
  counters = {};
}

ProjectedVertex project_vertex(const glm::vec4& clip, const SetupParams& params) {
  ProjectedVertex v;
  v.clip = clip;
  v.x = v.y = 0;
  v.z = 0.0f;
  if (!finite(clip)) {
    v.outcode = kNotFinite;
    return v;
  }
  const glm::dvec4 q(clip);
  v.outcode = clip_outcode(q, params.band);
  if (v.outcode == 0) {
    double z;
    snap(q, params, v.x, v.y, z);
    v.z = float(z);
  }
  return v;
}

void setup_triangle(const ProjectedVertex& pv0, const ProjectedVertex& pv1, const ProjectedVertex& pv2,
                    const RasterDraw& draw, uint32_t triangle_index, const SetupParams& params, SetupBatch& out) {
  ++out.counters.in;
  const uint32_t any_out = pv0.outcode | pv1.outcode | pv2.outcode;
  if ((any_out & kNotFinite) || (pv0.outcode & pv1.outcode & pv2.outcode)) {
    ++out.counters.culled;
    return;
  }
  // Every test below that drops the triangle counts it as culled, whichever
  // fails first: the cheap integer ones come first.
  int32_t xs[kMaxClippedVertices], ys[kMaxClippedVertices];
  PixelRect poly_bounds;
  if (any_out == 0) {
    xs[0] = pv0.x, xs[1] = pv1.x, xs[2] = pv2.x;
    ys[0] = pv0.y, ys[1] = pv1.y, ys[2] = pv2.y;
    if (params.cull == CullMode::Back && !draw.double_sided) {
      // Unclipped (all w > 0): the exact snapped area rejects back faces before
      // any floating-point work. Counter-clockwise in NDC (y up) is a negative
      // area in pixels (y down).
      const int64_t area = (int64_t(pv1.x) - pv0.x) * (int64_t(pv2.y) - pv0.y) -
                           (int64_t(pv2.x) - pv0.x) * (int64_t(pv1.y) - pv0.y);
      if (area == 0 || (area < 0) == draw.mirrored) {
        ++out.counters.culled;
        return;
      }
    }
    poly_bounds = pixel_bounds(xs, ys, 3, params);
    if (poly_bounds.empty()) {
      ++out.counters.culled;
      return;
    }
  }
  const glm::dvec4 v[3] = {glm::dvec4(pv0.clip), glm::dvec4(pv1.clip), glm::dvec4(pv2.clip)};
  // Columns (x, y, w) of M; rows of M^-1 are the cross products over det(M).
  const glm::dvec3 p0(v[0].x, v[0].y, v[0].w), p1(v[1].x, v[1].y, v[1].w), p2(v[2].x, v[2].y, v[2].w);
  const glm::dvec3 n[3] = {glm::cross(p1, p2), glm::cross(p2, p0), glm::cross(p0, p1)};
  const double det = glm::dot(p0, n[0]);
  // det > 0 iff the triangle is counter-clockwise in NDC as seen from the
  // eye; unlike a screen-space area this holds for vertices behind the eye too.
  if (!(det != 0.0) || !std::isfinite(det)) {
    ++out.counters.culled;
    return;
  }
  const bool ccw = det > 0.0;
  const bool front = ccw != draw.mirrored;
  if (params.cull == CullMode::Back && !draw.double_sided && !front) {
    ++out.counters.culled;
    return;
  }

  double zmin, zmax;
  int count = 3;
  if (any_out == 0) {
    zmin = std::min({pv0.z, pv1.z, pv2.z});
    zmax = std::max({pv0.z, pv1.z, pv2.z});
    // The only piece is the triangle itself: its winding after snapping.
    const int64_t area = (int64_t(xs[1]) - xs[0]) * (int64_t(ys[2]) - ys[0]) -
                         (int64_t(xs[2]) - xs[0]) * (int64_t(ys[1]) - ys[0]);
    if (area == 0 || (area < 0) != ccw) {
      ++out.counters.culled;
      return;
    }
  } else {
    ++out.counters.clipped;
    ClipPolygon poly;
    clip_triangle(v[0], v[1], v[2], any_out, params.band, poly);
    count = poly.count;
    zmin = HUGE_VAL, zmax = -HUGE_VAL;
    for (int i = 0; i < count; ++i) {
      if (!(poly.v[i].w > 0.0)) {  // only a degenerate matrix gets here (w >= z >= 0 after clipping)
        count = 0;
        break;
      }
      double z;
      snap(poly.v[i], params, xs[i], ys[i], z);
      zmin = std::min(zmin, z);
      zmax = std::max(zmax, z);
    }
    if (count < 3) {
      ++out.counters.culled;
      return;
    }
    poly_bounds = pixel_bounds(xs, ys, count, params);
    if (poly_bounds.empty()) {
      ++out.counters.culled;
      return;
    }
  }

  // Interpolation planes of the original triangle in pixel units, relative to
  // the polygon's first pixel centre. ndc = (2 px / W - 1, 1 - 2 py / H).
  const double ref_x = poly_bounds.x0 + 0.5, ref_y = poly_bounds.y0 + 0.5;
  const double qx = 2.0 * ref_x / params.width - 1.0, qy = 1.0 - 2.0 * ref_y / params.height;
  const double inv_det = 1.0 / det, sx = params.sx, sy = params.sy;
  const uint32_t interp_index = uint32_t(out.interps.size());
  TriangleInterp& ti = out.interps.push_uninit();
  double z0 = 0.0, zx = 0.0, zy = 0.0;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 row = n[i] * inv_det;
    const double u0 = row.x * qx + row.y * qy + row.z, ux = row.x * sx, uy = row.y * sy;
    ti.u0[i] = float(u0);
    ti.ux[i] = float(ux);
    ti.uy[i] = float(uy);
    z0 += u0 * v[i].z;
    zx += ux * v[i].z;
    zy += uy * v[i].z;
  }
  ti.ref_x = float(ref_x);
  ti.ref_y = float(ref_y);
  ti.draw_index = draw.draw_index;
  ti.triangle_index = triangle_index;
  ti.front_facing = front;

  uint64_t pieces = 0;
  for (int k = 1; k + 1 < count; ++k) {
    int32_t x[3] = {xs[0], xs[k], xs[k + 1]}, y[3] = {ys[0], ys[k], ys[k + 1]};
    if (any_out != 0) {  // (an unclipped triangle's winding was checked above)
      const int64_t area = (int64_t(x[1]) - x[0]) * (int64_t(y[2]) - y[0]) -
                           (int64_t(x[2]) - x[0]) * (int64_t(y[1]) - y[0]);
      // Counter-clockwise in NDC (y up) is clockwise in pixels (y down): area < 0.
      // Zero area or a winding flipped by snapping leaves nothing to draw.
      if (area == 0 || (area < 0) != ccw) continue;
    }
    if (ccw) {  // area < 0: make it counter-clockwise in pixels (positive area)
      std::swap(x[1], x[2]);
      std::swap(y[1], y[2]);
    }
    const PixelRect r = count == 3 ? poly_bounds : pixel_bounds(x, y, 3, params);
    if (r.empty()) continue;
    ++pieces;
    ScreenTriangle& t = out.triangles.push_uninit();
    set_edge(t, 0, x[0], y[0], x[1], y[1]);
    set_edge(t, 1, x[1], y[1], x[2], y[2]);
    set_edge(t, 2, x[2], y[2], x[0], y[0]);
    t.small = std::max({x[0], x[1], x[2]}) - std::min({x[0], x[1], x[2]}) <= kSmallExtent &&
              std::max({y[0], y[1], y[2]}) - std::min({y[0], y[1], y[2]}) <= kSmallExtent;
    t.tiny = t.small && params.sample_margin == 0 && r.x1 - r.x0 < kTinySize && r.y1 - r.y0 < kTinySize;
    t.mask = 0;
    if (t.tiny) {
      t.mask = tiny_coverage(t, r);
      if (t.mask == 0) {  // covers no pixel centre: nothing to rasterise
        out.triangles.pop_back();
        continue;
      }
    }
    t.z0 = float(z0);
    t.zx = float(zx);
    t.zy = float(zy);
    t.z_min = float(zmin);
    t.z_max = float(zmax);
    t.ref_x = poly_bounds.x0;
    t.ref_y = poly_bounds.y0;
    t.id = out.id_base + interp_index;
    t.interp = interp_index;
    t.alpha_mask = draw.alpha_mask;
    out.bounds.push_uninit() = r;
  }
  if (pieces == 0) {
    out.interps.pop_back();
    ++out.counters.culled;
    return;
  }
  ++out.counters.visible;
  out.counters.screen += pieces;
}

}  // namespace cr

#include "engine/raster/triangle_setup.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "engine/core/error.h"

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
inline PixelRect pixel_bounds(const int32_t* xs, const int32_t* ys, int n, const SetupParams& p) {
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
  if (r.x1 - r.x0 < 2 && r.y1 - r.y0 < 2) {  // up to 2x2 pixels (most tiny triangles): one by one
    uint64_t mask = 0;
    for (int j = 0; j <= r.y1 - r.y0; ++j)
      for (int i = 0; i <= r.x1 - r.x0; ++i) {
        bool in = true;
        for (int e = 0; e < 3; ++e) in &= t.c(e) + int64_t(t.a[e]) * (r.x0 + i) + int64_t(t.b[e]) * (r.y0 + j) >= 0;
        mask |= uint64_t(in) << (kTinySize * j + i);
      }
    return mask;
  }
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

namespace {

// Interpolation planes of the original triangle (rows of M^-1 = n / det) in
// pixel units, relative to the first pixel centre of `bounds`, into ti; the
// NDC depth plane z0 + zx dx + zy dy of the same reference.
// ndc = (2 px / W - 1, 1 - 2 py / H).
void interpolation_planes(const glm::dvec3 (&n)[3], double det, const glm::dvec4 (&v)[3], const PixelRect& bounds,
                          const SetupParams& params, TriangleInterp& ti, double& z0, double& zx, double& zy) {
  const double ref_x = bounds.x0 + 0.5, ref_y = bounds.y0 + 0.5;
  const double qx = 2.0 * ref_x / params.width - 1.0, qy = 1.0 - 2.0 * ref_y / params.height;
  const double inv_det = 1.0 / det, sx = params.sx, sy = params.sy;
  z0 = 0.0, zx = 0.0, zy = 0.0;
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
}

// Edges and size class of the piece with vertices (x, y) (positive area in
// pixels) and pixel bounds r; false when it is tiny and covers no pixel centre.
bool set_piece(ScreenTriangle& t, const int32_t (&x)[3], const int32_t (&y)[3], const PixelRect& r,
               const SetupParams& params) {
  set_edge(t, 0, x[0], y[0], x[1], y[1]);
  set_edge(t, 1, x[1], y[1], x[2], y[2]);
  set_edge(t, 2, x[2], y[2], x[0], y[0]);
  t.small = std::max({x[0], x[1], x[2]}) - std::min({x[0], x[1], x[2]}) <= kSmallExtent &&
            std::max({y[0], y[1], y[2]}) - std::min({y[0], y[1], y[2]}) <= kSmallExtent;
  t.tiny = t.small && params.sample_margin == 0 && r.x1 - r.x0 < kTinySize && r.y1 - r.y0 < kTinySize;
  t.mask = t.tiny ? tiny_coverage(t, r) : 0;
  return !t.tiny || t.mask != 0;
}

// Whether the triangle with this clip-space determinant is dropped: a
// degenerate or non-finite one always, a back face of a single-sided draw
// when culling. det > 0 iff the triangle is counter-clockwise in NDC as seen
// from the eye; unlike a screen-space area this holds for vertices behind the
// eye too.
bool facing_culled(double det, const RasterDraw& draw, const SetupParams& params) {
  if (!(det != 0.0) || !std::isfinite(det)) return true;
  const bool front = (det > 0.0) != draw.mirrored;
  return params.cull == CullMode::Back && !draw.double_sided && !front;
}

void set_depth(ScreenTriangle& t, double z0, double zx, double zy, double zmin, double zmax, const PixelRect& ref) {
  t.z0 = float(z0);
  t.zx = float(zx);
  t.zy = float(zy);
  t.z_min = float(zmin);
  t.z_max = float(zmax);
  t.ref_x = ref.x0;
  t.ref_y = ref.y0;
}

}  // namespace

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
  if (facing_culled(det, draw, params)) {
    ++out.counters.culled;
    return;
  }
  const bool ccw = det > 0.0;
  const bool front = ccw != draw.mirrored;

  if (any_out == 0) {
    // Unclipped: the only piece is the triangle itself. Counter-clockwise in
    // NDC (y up) is clockwise in pixels (y down): area < 0. Zero area or a
    // winding flipped by snapping leaves nothing to draw.
    const int64_t area = (int64_t(xs[1]) - xs[0]) * (int64_t(ys[2]) - ys[0]) -
                         (int64_t(xs[2]) - xs[0]) * (int64_t(ys[1]) - ys[0]);
    if (area == 0 || (area < 0) != ccw) {
      ++out.counters.culled;
      return;
    }
    const int32_t x[3] = {xs[0], ccw ? xs[2] : xs[1], ccw ? xs[1] : xs[2]};
    const int32_t y[3] = {ys[0], ccw ? ys[2] : ys[1], ccw ? ys[1] : ys[2]};
    const uint32_t interp_index = uint32_t(out.interps.size());
    TriangleInterp& ti = out.interps.push_uninit();
    ++out.counters.visible;
    ++out.counters.screen;
    ScreenTriangle& t = out.triangles.push_uninit();
    if (!set_piece(t, x, y, poly_bounds, params)) {
      // Tiny and covering no pixel centre: it keeps its id, which nothing
      // will report, so its interpolation planes are never computed.
      out.triangles.pop_back();
      return;
    }
    double z0, zx, zy;
    interpolation_planes(n, det, v, poly_bounds, params, ti, z0, zx, zy);
    ti.draw_index = draw.draw_index;
    ti.triangle_index = triangle_index;
    ti.front_facing = front;
    set_depth(t, z0, zx, zy, std::min({pv0.z, pv1.z, pv2.z}), std::max({pv0.z, pv1.z, pv2.z}), poly_bounds);
    t.id = out.id_base + interp_index;
    t.interp = interp_index;
    t.alpha_mask = draw.alpha_mask;
    out.bounds.push_uninit() = poly_bounds;
    return;
  }

  ++out.counters.clipped;
  ClipPolygon poly;
  clip_triangle(v[0], v[1], v[2], any_out, params.band, poly);
  int count = poly.count;
  double zmin = HUGE_VAL, zmax = -HUGE_VAL;
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

  const uint32_t interp_index = uint32_t(out.interps.size());
  TriangleInterp& ti = out.interps.push_uninit();
  double z0, zx, zy;
  interpolation_planes(n, det, v, poly_bounds, params, ti, z0, zx, zy);
  ti.draw_index = draw.draw_index;
  ti.triangle_index = triangle_index;
  ti.front_facing = front;

  // The polygon as a fan of pieces.
  uint64_t pieces = 0;
  for (int k = 1; k + 1 < count; ++k) {
    int32_t x[3] = {xs[0], xs[k], xs[k + 1]}, y[3] = {ys[0], ys[k], ys[k + 1]};
    const int64_t area = (int64_t(x[1]) - x[0]) * (int64_t(y[2]) - y[0]) -
                         (int64_t(x[2]) - x[0]) * (int64_t(y[1]) - y[0]);
    if (area == 0 || (area < 0) != ccw) continue;
    if (area < 0) {
      std::swap(x[1], x[2]);
      std::swap(y[1], y[2]);
    }
    const PixelRect r = count == 3 ? poly_bounds : pixel_bounds(x, y, 3, params);
    if (r.empty()) continue;
    ++pieces;
    ScreenTriangle& t = out.triangles.push_uninit();
    if (!set_piece(t, x, y, r, params)) {  // tiny, covering no pixel centre
      out.triangles.pop_back();
      continue;
    }
    set_depth(t, z0, zx, zy, zmin, zmax, poly_bounds);
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

namespace {

// Lane-wise vectors of the batched setup (GCC vector extensions: one AVX-512
// register, or two AVX2 or four SSE2 ones, depending on the baseline).
constexpr int kLanes = 8;
typedef double d8 __attribute__((vector_size(8 * kLanes)));
typedef float f8 __attribute__((vector_size(4 * kLanes)));
typedef int32_t i8 __attribute__((vector_size(4 * kLanes)));
typedef int64_t l8 __attribute__((vector_size(8 * kLanes)));

template <typename V, typename T>
V load_lanes(const T* p) {
  V v;
  __builtin_memcpy(&v, p, sizeof(V));
  return v;
}
template <typename V, typename T>
void store_lanes(T* p, const V& v) {
  __builtin_memcpy(p, &v, sizeof(V));
}

// Triangles of one batch that passed the integer tests, in input order.
constexpr int kBatch = 64;
struct Candidates {
  int n = 0;
  uint32_t triangle[kBatch];
  uint32_t vertex[kBatch][3];
  bool clipped[kBatch];
  // Unclipped ones: snapped positions, pixel bounds, clip coordinates by vertex.
  int32_t x[3][kBatch], y[3][kBatch];
  int64_t area[kBatch];
  int32_t bx[kBatch], by[kBatch], bw[kBatch], bh[kBatch];  // bounds: first pixel, width and height
  PixelRect bounds[kBatch];
  float cx[3][kBatch], cy[3][kBatch], cz[3][kBatch], cw[3][kBatch];
  // The floating-point work (lanes of d8/f8).
  double det[kBatch];
  float u0[3][kBatch], ux[3][kBatch], uy[3][kBatch];
  float z0[kBatch], zx[kBatch], zy[kBatch];
  // The piece (lanes of i8/l8): set_edge's edges in the winding det gives,
  // size classes, and the mask of a tiny one within 2x2 pixels.
  int32_t a[3][kBatch], b[3][kBatch];
  int64_t c_num[3][kBatch];
  int32_t small[kBatch], tiny[kBatch];  // 0 or -1
  int64_t mask[kBatch];
};

// det(M) and the interpolation and depth planes of interpolation_planes(),
// written out operation by operation as glm::cross, glm::dot and that
// function evaluate them, for lanes [0, n) (rounded up: extra lanes hold
// whatever the arrays hold and are not used).
void batch_planes(Candidates& c, const SetupParams& params) {
  const d8 width = d8{} + double(params.width), height = d8{} + double(params.height);
  const d8 sx = d8{} + params.sx, sy = d8{} + params.sy;
  for (int l = 0; l < c.n; l += kLanes) {
    d8 x[3], y[3], z[3], w[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = __builtin_convertvector(load_lanes<f8>(&c.cx[k][l]), d8);
      y[k] = __builtin_convertvector(load_lanes<f8>(&c.cy[k][l]), d8);
      z[k] = __builtin_convertvector(load_lanes<f8>(&c.cz[k][l]), d8);
      w[k] = __builtin_convertvector(load_lanes<f8>(&c.cw[k][l]), d8);
    }
    // n[i] = cross(p[i+1], p[i+2]) with p = (x, y, w): (a.y b.z - b.y a.z, a.z b.x - b.z a.x, a.x b.y - b.x a.y).
    d8 nx[3], ny[3], nz[3];
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      nx[i] = y[a] * w[b] - y[b] * w[a];
      ny[i] = w[a] * x[b] - w[b] * x[a];
      nz[i] = x[a] * y[b] - x[b] * y[a];
    }
    const d8 det = (x[0] * nx[0] + y[0] * ny[0]) + w[0] * nz[0];  // dot(p0, n0)
    store_lanes(&c.det[l], det);
    const d8 ref_x = __builtin_convertvector(load_lanes<i8>(&c.bx[l]), d8) + 0.5;
    const d8 ref_y = __builtin_convertvector(load_lanes<i8>(&c.by[l]), d8) + 0.5;
    const d8 qx = 2.0 * ref_x / width - 1.0, qy = 1.0 - 2.0 * ref_y / height;
    const d8 inv_det = 1.0 / det;
    d8 z0 = d8{}, zx = d8{}, zy = d8{};
    for (int i = 0; i < 3; ++i) {
      const d8 rx = nx[i] * inv_det, ry = ny[i] * inv_det, rz = nz[i] * inv_det;
      const d8 u0 = rx * qx + ry * qy + rz, ux = rx * sx, uy = ry * sy;
      store_lanes(&c.u0[i][l], __builtin_convertvector(u0, f8));
      store_lanes(&c.ux[i][l], __builtin_convertvector(ux, f8));
      store_lanes(&c.uy[i][l], __builtin_convertvector(uy, f8));
      z0 += u0 * z[i];
      zx += ux * z[i];
      zy += uy * z[i];
    }
    store_lanes(&c.z0[l], __builtin_convertvector(z0, f8));
    store_lanes(&c.zx[l], __builtin_convertvector(zx, f8));
    store_lanes(&c.zy[l], __builtin_convertvector(zy, f8));
  }
}

// set_piece for lanes [0, n) (rounded up), in the winding of c.det: the
// integer edges exactly as set_edge computes them, and the coverage mask of
// tiny pieces within 2x2 pixels as tiny_coverage finds it.
void batch_edges(Candidates& c, const SetupParams& params) {
  const i8 zero = i8{};
  for (int l = 0; l < c.n; l += kLanes) {
    const i8 ccw = __builtin_convertvector(load_lanes<d8>(&c.det[l]) > 0.0, i8);  // -1: swap vertices 1 and 2
    i8 x[3], y[3];
    x[0] = load_lanes<i8>(&c.x[0][l]);
    y[0] = load_lanes<i8>(&c.y[0][l]);
    const i8 x1 = load_lanes<i8>(&c.x[1][l]), x2 = load_lanes<i8>(&c.x[2][l]);
    const i8 y1 = load_lanes<i8>(&c.y[1][l]), y2 = load_lanes<i8>(&c.y[2][l]);
    x[1] = (x2 & ccw) | (x1 & ~ccw);
    x[2] = (x1 & ccw) | (x2 & ~ccw);
    y[1] = (y2 & ccw) | (y1 & ~ccw);
    y[2] = (y1 & ccw) | (y2 & ~ccw);
    const l8 bx = __builtin_convertvector(load_lanes<i8>(&c.bx[l]), l8);
    const l8 by = __builtin_convertvector(load_lanes<i8>(&c.by[l]), l8);
    const i8 bw = load_lanes<i8>(&c.bw[l]), bh = load_lanes<i8>(&c.bh[l]);
    l8 a[3], b[3], edge_c[3];
    for (int e = 0; e < 3; ++e) {
      const int i = e, j = (e + 1) % 3;
      const i8 a32 = y[i] - y[j], b32 = x[j] - x[i];
      store_lanes(&c.a[e][l], a32);
      store_lanes(&c.b[e][l], b32);
      a[e] = __builtin_convertvector(a32, l8);
      b[e] = __builtin_convertvector(b32, l8);
      const l8 cc = -(a[e] * __builtin_convertvector(x[i], l8) + b[e] * __builtin_convertvector(y[i], l8));
      const l8 top_left = (a[e] > 0) | ((a[e] == 0) & (b[e] > 0));  // -1 where true
      const l8 c_num = int64_t(kSubpixelScale / 2) * (a[e] + b[e]) + cc - 1 - top_left;
      store_lanes(&c.c_num[e][l], c_num);
      edge_c[e] = c_num >> kSubpixelBits;
    }
    auto lo = [](i8 p, i8 q) { return (p & (p < q)) | (q & ~(p < q)); };
    auto hi = [](i8 p, i8 q) { return (p & (p > q)) | (q & ~(p > q)); };
    const i8 small = (hi(hi(x[0], x[1]), x[2]) - lo(lo(x[0], x[1]), x[2]) <= kSmallExtent) &
                     (hi(hi(y[0], y[1]), y[2]) - lo(lo(y[0], y[1]), y[2]) <= kSmallExtent);
    const i8 tiny = small & (params.sample_margin == 0 ? ~zero : zero) & (bw <= kTinySize) & (bh <= kTinySize);
    store_lanes(&c.small[l], small);
    store_lanes(&c.tiny[l], tiny);
    l8 mask = l8{};
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        l8 in = __builtin_convertvector((bw > i) & (bh > j), l8);
        for (int e = 0; e < 3; ++e) in &= edge_c[e] + a[e] * (bx + i) + b[e] * (by + j) >= 0;
        mask |= in & (int64_t(1) << (kTinySize * j + i));
      }
    store_lanes(&c.mask[l], mask);
  }
}

// The rest of setup_triangle for candidate i (unclipped), in input order.
void finish_candidate(const Candidates& c, int i, const ProjectedVertex* vertices, const RasterDraw& draw,
                      const SetupParams& params, SetupBatch& out) {
  const double det = c.det[i];
  if (facing_culled(det, draw, params)) {
    ++out.counters.culled;
    return;
  }
  const bool ccw = det > 0.0;
  const bool front = ccw != draw.mirrored;
  const int64_t area = c.area[i];
  if (area == 0 || (area < 0) != ccw) {
    ++out.counters.culled;
    return;
  }
  const uint32_t interp_index = uint32_t(out.interps.size());
  TriangleInterp& ti = out.interps.push_uninit();
  ++out.counters.visible;
  ++out.counters.screen;
  ScreenTriangle& t = out.triangles.push_uninit();
  const PixelRect& bounds = c.bounds[i];
  for (int e = 0; e < 3; ++e) {
    t.a[e] = c.a[e][i];
    t.b[e] = c.b[e][i];
    t.c_num[e] = c.c_num[e][i];
  }
  t.small = c.small[i] != 0;
  t.tiny = c.tiny[i] != 0;
  t.mask = 0;
  if (t.tiny) {
    t.mask = c.bw[i] <= 2 && c.bh[i] <= 2 ? uint64_t(c.mask[i]) : tiny_coverage(t, bounds);
    if (t.mask == 0) {  // tiny, covering no pixel centre (see setup_triangle)
      out.triangles.pop_back();
      return;
    }
  }
  for (int k = 0; k < 3; ++k) {
    ti.u0[k] = c.u0[k][i];
    ti.ux[k] = c.ux[k][i];
    ti.uy[k] = c.uy[k][i];
  }
  ti.ref_x = float(bounds.x0 + 0.5);
  ti.ref_y = float(bounds.y0 + 0.5);
  ti.draw_index = draw.draw_index;
  ti.triangle_index = c.triangle[i];
  ti.front_facing = front;
  const ProjectedVertex &v0 = vertices[c.vertex[i][0]], &v1 = vertices[c.vertex[i][1]], &v2 = vertices[c.vertex[i][2]];
  t.z0 = c.z0[i];
  t.zx = c.zx[i];
  t.zy = c.zy[i];
  t.z_min = std::min({v0.z, v1.z, v2.z});
  t.z_max = std::max({v0.z, v1.z, v2.z});
  t.ref_x = bounds.x0;
  t.ref_y = bounds.y0;
  t.id = out.id_base + interp_index;
  t.interp = interp_index;
  t.alpha_mask = draw.alpha_mask;
  out.bounds.push_uninit() = bounds;
}

}  // namespace

void setup_triangles(const ProjectedVertex* vertices, size_t vertex_count, const RasterDraw& draw, uint32_t first,
                     uint32_t count, const SetupParams& params, SetupBatch& out) {
  const uint32_t* indices = draw.primitive->indices.data();
  const bool cull_back = params.cull == CullMode::Back && !draw.double_sided;
  Candidates c;
  for (uint32_t begin = first; begin < first + count; begin += kBatch) {
    const uint32_t end = std::min(first + count, begin + uint32_t(kBatch));
    // The integer tests of setup_triangle, in order, keeping the candidates.
    c.n = 0;
    for (uint32_t tri = begin; tri < end; ++tri) {
      const uint32_t* idx = &indices[3 * size_t(tri)];
      if (idx[0] >= vertex_count || idx[1] >= vertex_count || idx[2] >= vertex_count)
        throw Error("rasterizer: draw " + std::to_string(draw.draw_index) + " triangle " + std::to_string(tri) +
                    " indexes a vertex out of range");
      const ProjectedVertex &v0 = vertices[idx[0]], &v1 = vertices[idx[1]], &v2 = vertices[idx[2]];
      ++out.counters.in;
      const uint32_t any_out = v0.outcode | v1.outcode | v2.outcode;
      if ((any_out & kNotFinite) || (v0.outcode & v1.outcode & v2.outcode)) {
        ++out.counters.culled;
        continue;
      }
      const int i = c.n;
      c.triangle[i] = tri;
      c.vertex[i][0] = idx[0], c.vertex[i][1] = idx[1], c.vertex[i][2] = idx[2];
      c.clipped[i] = any_out != 0;
      if (any_out != 0) {  // set up on its own below; harmless lanes meanwhile
        c.bx[i] = c.by[i] = c.bw[i] = c.bh[i] = 0;
        for (int k = 0; k < 3; ++k) {
          c.cx[k][i] = c.cy[k][i] = c.cz[k][i] = c.cw[k][i] = 1.0f;
          c.x[k][i] = c.y[k][i] = 0;
        }
      } else {
        const int64_t area = (int64_t(v1.x) - v0.x) * (int64_t(v2.y) - v0.y) - (int64_t(v2.x) - v0.x) * (int64_t(v1.y) - v0.y);
        if (cull_back && (area == 0 || (area < 0) == draw.mirrored)) {
          ++out.counters.culled;
          continue;
        }
        const int32_t x[3] = {v0.x, v1.x, v2.x}, y[3] = {v0.y, v1.y, v2.y};
        const PixelRect r = pixel_bounds(x, y, 3, params);
        if (r.empty()) {
          ++out.counters.culled;
          continue;
        }
        for (int k = 0; k < 3; ++k) {
          c.x[k][i] = x[k];
          c.y[k][i] = y[k];
        }
        c.area[i] = area;
        c.bounds[i] = r;
        c.bx[i] = r.x0;
        c.by[i] = r.y0;
        c.bw[i] = r.x1 - r.x0 + 1;
        c.bh[i] = r.y1 - r.y0 + 1;
        const ProjectedVertex* v[3] = {&v0, &v1, &v2};
        for (int k = 0; k < 3; ++k) {
          c.cx[k][i] = v[k]->clip.x;
          c.cy[k][i] = v[k]->clip.y;
          c.cz[k][i] = v[k]->clip.z;
          c.cw[k][i] = v[k]->clip.w;
        }
      }
      ++c.n;
    }
    // Lanes past the last candidate: harmless values (their results are not read).
    for (int i = c.n; i < (c.n + kLanes - 1) / kLanes * kLanes; ++i) {
      c.bx[i] = c.by[i] = c.bw[i] = c.bh[i] = 0;
      for (int k = 0; k < 3; ++k) {
        c.cx[k][i] = c.cy[k][i] = c.cz[k][i] = c.cw[k][i] = 1.0f;
        c.x[k][i] = c.y[k][i] = 0;
      }
    }
    batch_planes(c, params);
    batch_edges(c, params);
    for (int i = 0; i < c.n; ++i) {
      if (!c.clipped[i]) {
        finish_candidate(c, i, vertices, draw, params, out);
        continue;
      }
      // Clipped: setup_triangle from the start (it counts the triangle in again).
      --out.counters.in;
      setup_triangle(vertices[c.vertex[i][0]], vertices[c.vertex[i][1]], vertices[c.vertex[i][2]], draw, c.triangle[i],
                     params, out);
    }
  }
}

void project_vertices(const glm::vec3* positions, size_t count, const glm::mat4& m, const SetupParams& params,
                      ProjectedVertex* out) {
  const d8 half_width = d8{} + 0.5 * params.width, half_height = d8{} + 0.5 * params.height;
  const d8 gx = d8{} + params.band.gx, gy = d8{} + params.band.gy;
  const f8 one = f8{} + 1.0f;
  size_t i = 0;
  for (; i + kLanes <= count; i += kLanes) {
    float px[kLanes], py[kLanes], pz[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      px[l] = positions[i + l].x;
      py[l] = positions[i + l].y;
      pz[l] = positions[i + l].z;
    }
    const f8 x = load_lanes<f8>(px), y = load_lanes<f8>(py), z = load_lanes<f8>(pz);
    // glm's mat4 * vec4: (m[0] x + m[1] y) + (m[2] z + m[3] w), w = 1.
    f8 clip[4];
    for (int k = 0; k < 4; ++k)
      clip[k] = (m[0][k] * x + m[1][k] * y) + (m[2][k] * z + m[3][k] * one);
    // Finite: |v| <= FLT_MAX (false for NaN and infinities).
    i8 finite = ~i8{};
    for (int k = 0; k < 4; ++k) finite &= (clip[k] <= 3.40282347e+38f) & (clip[k] >= -3.40282347e+38f);
    const d8 qx = __builtin_convertvector(clip[0], d8), qy = __builtin_convertvector(clip[1], d8);
    const d8 qz = __builtin_convertvector(clip[2], d8), qw = __builtin_convertvector(clip[3], d8);
    // clip_outcode: bit p where plane p's distance is negative.
    const l8 code = ((qw - qz < 0.0) & 1) | ((qz < 0.0) & 2) | ((gx * qw - qx < 0.0) & 4) | ((gx * qw + qx < 0.0) & 8) |
                    ((gy * qw - qy < 0.0) & 16) | ((gy * qw + qy < 0.0) & 32);
    const i8 outcode = (__builtin_convertvector(code, i8) & finite) | (int32_t(kNotFinite) & ~finite);
    // snap(): where the vertex is inside every plane (other lanes: 0, as project_vertex leaves them).
    const l8 inside = __builtin_convertvector(outcode == 0, l8);
    const d8 inv_w = 1.0 / qw;
    const d8 sx = (qx * inv_w + 1.0) * half_width, sy = (1.0 - qy * inv_w) * half_height;
    const d8 fx = sx * double(kSubpixelScale), fy = sy * double(kSubpixelScale);
    // round_to_int: halves away from zero, then truncation.
    d8 rx = fx >= 0.0 ? fx + 0.5 : fx - 0.5, ry = fy >= 0.0 ? fy + 0.5 : fy - 0.5;
    rx = inside ? rx : 0.0;
    ry = inside ? ry : 0.0;
    const d8 nz = inside ? qz * inv_w : 0.0;
    int32_t ox[kLanes], oy[kLanes], oc[kLanes];
    float oz[kLanes], cx[kLanes], cy[kLanes], cz[kLanes], cw[kLanes];
    store_lanes(ox, __builtin_convertvector(rx, i8));
    store_lanes(oy, __builtin_convertvector(ry, i8));
    store_lanes(oc, outcode);
    store_lanes(oz, __builtin_convertvector(nz, f8));
    store_lanes(cx, clip[0]);
    store_lanes(cy, clip[1]);
    store_lanes(cz, clip[2]);
    store_lanes(cw, clip[3]);
    for (int l = 0; l < kLanes; ++l) {
      ProjectedVertex& v = out[i + l];
      v.clip = glm::vec4(cx[l], cy[l], cz[l], cw[l]);
      v.x = ox[l];
      v.y = oy[l];
      v.z = oz[l];
      v.outcode = uint32_t(oc[l]);
    }
  }
  for (; i < count; ++i) out[i] = project_vertex(m * glm::vec4(positions[i], 1.0f), params);
}

}  // namespace cr

// Fitting and sampling of the sun's shadow map (shadow_map.h).
//
// Texel layout shared with the rasterizer that renders it: NDC (x, y) of
// light_view_proj map to texel column (x + 1) / 2 * size and row
// (1 - y) / 2 * size (row 0 at y = +1, as in the frame buffers), texel
// centres at integer + 0.5; depth[row * size + column] holds the largest
// NDC z of the texel centre's ray (reversed: 1 nearest the sun, 0 empty).
//
// Bias. A receiver is moved along its normal by
//   offset = kNormalOffsetTexels * (pcf_radius + 1) * texel * sin(theta),
// theta the angle between normal and sun, then compared with a constant
// margin of kConstantBiasTexels texels plus a few float ulps. Why this is
// enough on any plane: PCF compares the receiver with depths stored up to
// (r + 1) texels away in x and in y, i.e. up to (r + 1) sqrt(2) texels along
// the plane's depth gradient, over which the plane's own depth changes by
// (r + 1) sqrt(2) texel tan(theta). Lifting the receiver by h off its plane
// puts it h / cos(theta) nearer the sun, so h = 1.5 (r + 1) texel sin(theta)
// clears its own plane at every sun angle without a tan() that blows up at
// grazing light (no acne). The lift is at most 1.5 (r + 1) texels and only
// along the normal, so shadows still start at the foot of an object standing
// on the ground (no peter-panning); gaps thinner than that lift (a slab
// hovering within ~3 texels of the ground) leak light, the usual price.
#include "engine/shading/shadow_map.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <xmmintrin.h>

#include "engine/shading/small_floor.h"

namespace cr {
namespace {

constexpr float kNormalOffsetTexels = 1.5f;
constexpr float kConstantBiasTexels = 0.5f;
// Rounding of the rasterizer's depth interpolation near z = 1 (ulp 6e-8).
constexpr float kDepthEpsilon = 1.0f / (1 << 20);

// Unit axes of the light's view: x, y across the map, z towards the sun.
struct LightBasis {
  glm::dvec3 x, y, z;
};

LightBasis light_basis(const glm::vec3& direction_to_sun) {
  LightBasis b;
  const glm::dvec3 d(direction_to_sun);
  const double len = glm::length(d);
  b.z = len > 0.0 && std::isfinite(len) ? d / len : glm::dvec3(0.0, 1.0, 0.0);
  // A fixed reference axis keeps the map's orientation (and so its texel
  // grid) independent of the camera; switch it near the zenith.
  const glm::dvec3 ref = std::abs(b.z.y) > 0.99 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  b.x = glm::normalize(glm::cross(ref, b.z));
  b.y = glm::cross(b.z, b.x);
  return b;
}

// How the taps of the n x n block at (x0, y0) compare with `receiver`: lit
// where the depth is at most the receiver's. Four at a time (one compare per
// row for the default 3x3 PCF's 4x4 block), the lanes only ANDed and ORed.
enum class TapAgreement { AllLit, AllShadowed, Mixed };
[[gnu::always_inline]] inline TapAgreement compare_taps(const float* depth, int size, int x0, int y0, int n,
                                                        float receiver) {
  using float4 = float __attribute__((vector_size(16)));
  using int4 = int __attribute__((vector_size(16)));
  const float4 bound = {receiver, receiver, receiver, receiver};
  int4 lit_everywhere = {-1, -1, -1, -1};  // per lane: every tap so far lit
  int4 lit_somewhere = {0, 0, 0, 0};       // per lane: some tap so far lit
  bool tail_all_lit = true, tail_any_lit = false;
  for (int y = y0; y < y0 + n; ++y) {
    const float* row = depth + size_t(y) * size_t(size) + size_t(x0);
    int x = 0;
    for (; x + 4 <= n; x += 4) {
      float4 taps;
      std::memcpy(&taps, row + x, sizeof(taps));
      const int4 lit = taps <= bound;  // true lanes are -1
      lit_everywhere &= lit;
      lit_somewhere |= lit;
    }
    for (; x < n; ++x) {
      const bool lit = row[x] <= receiver;
      tail_all_lit &= lit;
      tail_any_lit |= lit;
    }
  }
  if (tail_all_lit && _mm_movemask_ps(__m128(lit_everywhere)) == 0xF) return TapAgreement::AllLit;
  if (!tail_any_lit && _mm_movemask_ps(__m128(lit_somewhere)) == 0) return TapAgreement::AllShadowed;
  return TapAgreement::Mixed;
}

}  // namespace

ShadowFit fit_shadow_view(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance, int size,
                          const glm::vec3& scene_min, const glm::vec3& scene_max) {
  ShadowFit fit;
  fit.size = size;
  if (size <= 0) return fit;
  const LightBasis basis = light_basis(direction_to_sun);
  fit.axis_x = basis.x;
  fit.axis_y = basis.y;
  fit.axis_z = basis.z;

  // Bounding sphere of the frustum slice [near, far]: its centre on the view
  // axis at distance c equalises the distances to the near and far corners,
  // (c - n)^2 + n^2 k^2 = (f - c)^2 + f^2 k^2 with k the corner slope, unless
  // c would pass the far plane. It depends only on fov, aspect and distances,
  // so rotating the camera never changes the map's scale.
  // An orthographic view's slice is a box: its sphere is centred half way.
  const double n = std::max(double(view.znear), 1e-6);
  double f = std::max(double(shadow_distance), 2.0 * n);
  double c = 0.0, radius = 0.0;
  if (view.orthographic) {
    f = std::max(std::min(f, double(view.zfar)), 2.0 * n);
    const double hh = double(view.ortho_half_height), hw = hh * double(view.aspect);
    c = 0.5 * (f + n);
    radius = std::sqrt(0.25 * (f - n) * (f - n) + hw * hw + hh * hh);
  } else {
    const double ty = std::tan(0.5 * double(view.vfov_rad));
    const double k2 = ty * ty * (1.0 + double(view.aspect) * double(view.aspect));
    c = std::min(0.5 * (f + n) * (1.0 + k2), f);
    radius = std::sqrt(std::max((c - n) * (c - n) + n * n * k2, (f - c) * (f - c) + f * f * k2));
  }
  const glm::dvec3 centre = view.position + glm::dvec3(view.forward) * c;

  // Two spare texels: snapping moves the centre by up to half a texel per
  // axis, and the sphere must stay inside the map.
  fit.texel = 2.0 * radius / std::max(size - 2, 1);
  // Snap the centre to the world-aligned texel grid of the light's view, so
  // a translating camera moves the map by whole texels (no shimmering).
  fit.grid_x = int64_t(std::floor(glm::dot(centre, basis.x) / fit.texel + 0.5));
  fit.grid_y = int64_t(std::floor(glm::dot(centre, basis.y) / fit.texel + 0.5));
  fit.centre_depth = glm::dot(centre, basis.z);

  // Depth: receivers lie within the sphere; casters may be anywhere between
  // it and the sun, so the near (sunward) end reaches the scene's bounds.
  const glm::dvec3 origin = basis.x * (double(fit.grid_x) * fit.texel) + basis.y * (double(fit.grid_y) * fit.texel) +
                            basis.z * fit.centre_depth;
  double toward_sun = radius;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? scene_max.x : scene_min.x, (i & 2) ? scene_max.y : scene_min.y,
                            (i & 4) ? scene_max.z : scene_min.z);
    const double d = glm::dot(corner - origin, basis.z);
    if (std::isfinite(d)) toward_sun = std::max(toward_sun, d);
  }
  fit.need_max = toward_sun + fit.texel;
  fit.need_min = -radius - fit.texel;
  return fit;
}

ShadowMap shadow_projection(const ShadowFit& fit, int pcf_radius, double origin_depth, double depth_min,
                            double depth_max) {
  ShadowMap m;
  if (fit.size <= 0) return m;
  const double half_extent = 0.5 * fit.size * fit.texel;
  m.origin = fit.axis_x * (double(fit.grid_x) * fit.texel) + fit.axis_y * (double(fit.grid_y) * fit.texel) +
             fit.axis_z * origin_depth;
  const double range = depth_max - depth_min;

  // Rows of the orthographic projection of (world - origin).
  glm::dmat4 p(0.0);
  for (int j = 0; j < 3; ++j) {
    p[j][0] = fit.axis_x[j] / half_extent;
    p[j][1] = fit.axis_y[j] / half_extent;
    p[j][2] = fit.axis_z[j] / range;
  }
  p[3][2] = -depth_min / range;
  p[3][3] = 1.0;

  m.size = fit.size;
  m.light_view_proj = glm::mat4(p);
  m.texel_world_size = float(fit.texel);
  m.depth_range = float(range);
  m.direction_to_sun = glm::vec3(fit.axis_z);
  m.pcf_radius = std::max(pcf_radius, 0);
  m.grid_x = fit.grid_x;
  m.grid_y = fit.grid_y;
  m.origin_depth = origin_depth;
  m.depth_min = depth_min;
  m.depth_max = depth_max;
  return m;
}

ShadowMap fit_shadow_projection(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance, int size,
                                int pcf_radius, const glm::vec3& scene_min, const glm::vec3& scene_max) {
  const ShadowFit fit = fit_shadow_view(view, direction_to_sun, shadow_distance, size, scene_min, scene_max);
  return shadow_projection(fit, pcf_radius, fit.centre_depth, fit.need_min, fit.need_max);
}

ShadowMap fit_shadow_map(const Camera& view, const glm::vec3& direction_to_sun, float shadow_distance, int size,
                         int pcf_radius, const glm::vec3& scene_min, const glm::vec3& scene_max) {
  ShadowMap m = fit_shadow_projection(view, direction_to_sun, shadow_distance, size, pcf_radius, scene_min, scene_max);
  m.depth.assign(size_t(m.size) * size_t(m.size), 0.0f);
  return m;
}

namespace {

// The constants of one map's lookups, each rounded as visibility() rounds it.
struct LookupConstants {
  float offset_scale;  // kNormalOffsetTexels * (r + 1) * texel: the normal offset at sin(theta) = 1
  float depth_bias;    // kConstantBiasTexels * texel / depth_range
  float size;

  explicit LookupConstants(const ShadowMap& m)
      : offset_scale(kNormalOffsetTexels * float(std::max(m.pcf_radius, 0) + 1) * m.texel_world_size),
        depth_bias(kConstantBiasTexels * m.texel_world_size / m.depth_range),
        size(float(m.size)) {}
};

// Where a receiver reads the map: its texel coordinates and biased depth.
// False when the map recorded nothing there (lit). Inlined into a loop over
// many points it vectorises: glm's mat4 * vec4 is written out in glm's own
// order, (m0 x + m1 y) + (m2 z + m3 * 1), so the floats are visibility()'s.
[[gnu::always_inline]] inline bool project_receiver(const ShadowMap& m, const LookupConstants& c, float px, float py,
                                                    float pz, float nx, float ny, float nz, float& tx, float& ty,
                                                    float& receiver) {
  const glm::vec3 d = m.direction_to_sun;
  const float cos_theta = std::clamp(nx * d.x + ny * d.y + nz * d.z, -1.0f, 1.0f);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float offset = c.offset_scale * sin_theta;
  const float x = float(double(px) - m.origin.x + double(nx * offset));
  const float y = float(double(py) - m.origin.y + double(ny * offset));
  const float z = float(double(pz) - m.origin.z + double(nz * offset));
  const glm::mat4& p = m.light_view_proj;
  const float cx = (p[0][0] * x + p[1][0] * y) + (p[2][0] * z + p[3][0]);
  const float cy = (p[0][1] * x + p[1][1] * y) + (p[2][1] * z + p[3][1]);
  const float cz = (p[0][2] * x + p[1][2] * y) + (p[2][2] * z + p[3][2]);
  receiver = cz + c.depth_bias + kDepthEpsilon;
  tx = (cx * 0.5f + 0.5f) * c.size - 0.5f;
  ty = (0.5f - cy * 0.5f) * c.size - 0.5f;
  return std::abs(cx) <= 1.0f && std::abs(cy) <= 1.0f && cz >= 0.0f && cz <= 1.0f;
}

// The PCF filter's weighted sum over the taps around texel (x0, y0), (ax, ay)
// the point's offset from it: a (2r+1)-texel box filter centred on the point,
// taps weighted by their overlap with it. The edge rows and columns get the
// bilinear fractions, so visibility varies continuously as the point moves.
// Out of line: only penumbra and border points get here.
[[gnu::noinline]] float weighted_taps(const ShadowMap& m, int x0, int y0, float ax, float ay, float receiver) {
  const int r = std::max(m.pcf_radius, 0);
  const int size = m.size;
  const std::vector<float>& depth = m.depth;
  float lit = 0.0f;
  float shadowed = 0.0f;
  for (int dy = -r; dy <= r + 1; ++dy) {
    const float wy = dy == -r ? 1.0f - ay : (dy == r + 1 ? ay : 1.0f);
    const int y = y0 + dy;
    for (int dx = -r; dx <= r + 1; ++dx) {
      const float wx = dx == -r ? 1.0f - ax : (dx == r + 1 ? ax : 1.0f);
      const int x = x0 + dx;
      // Taps beyond the border have no occluder recorded.
      const bool in_map = x >= 0 && y >= 0 && x < size && y < size;
      if (!in_map || depth[size_t(y) * size_t(size) + size_t(x)] <= receiver) {
        lit += wx * wy;
      } else {
        shadowed += wx * wy;
      }
    }
  }
  // Both sums, so that fully lit and fully shadowed come out exactly 1 and 0
  // whatever the rounding of the weights.
  if (!(shadowed > 0.0f)) return 1.0f;
  if (!(lit > 0.0f)) return 0.0f;
  return lit / (lit + shadowed);
}

// The PCF filter around texel coordinates (tx, ty) inside the map. Inlined
// into the lookup loops: most points end at the all-lit/all-shadowed test.
[[gnu::always_inline]] inline float filter_taps(const ShadowMap& m, float tx, float ty, float receiver) {
  const int r = std::max(m.pcf_radius, 0);
  const int size = m.size;
  // |clip.x|, |clip.y| <= 1: small, finite texel coordinates.
  const int x0 = floor_to_int(tx);
  const int y0 = floor_to_int(ty);
  // Taps wholly inside the map (nearly every point) need no border test, and
  // where all of them agree (all but the penumbra) the weights do not matter:
  // the weighted sums would come out exactly 1 or 0.
  if (x0 - r >= 0 && y0 - r >= 0 && x0 + r + 1 < size && y0 + r + 1 < size) {
    // The default 3x3 PCF's 4x4 block gets the loop unrolled for it.
    const int n = 2 * r + 2;
    const TapAgreement taps = n == 4 ? compare_taps(m.depth.data(), size, x0 - r, y0 - r, 4, receiver)
                                     : compare_taps(m.depth.data(), size, x0 - r, y0 - r, n, receiver);
    if (taps == TapAgreement::AllLit) return 1.0f;
    // All shadowed: the weights are products of per-axis weights >= 0 that
    // sum to at least 1 per axis, so the shadowed sum is positive, lit zero.
    if (taps == TapAgreement::AllShadowed) return 0.0f;
  }
  return weighted_taps(m, x0, y0, tx - float(x0), ty - float(y0), receiver);
}

}  // namespace

float ShadowMap::visibility(const glm::vec3& world_pos, const glm::vec3& normal) const {
  if (size <= 0 || depth.size() < size_t(size) * size_t(size)) return 1.0f;
  float tx, ty, receiver;
  if (!project_receiver(*this, LookupConstants(*this), world_pos.x, world_pos.y, world_pos.z, normal.x, normal.y,
                        normal.z, tx, ty, receiver))
    return 1.0f;
  return filter_taps(*this, tx, ty, receiver);
}

void ShadowMap::visibility(const ShadowReceivers& points, float* out) const {
  const int n = points.count;
  if (size <= 0 || depth.size() < size_t(size) * size_t(size)) {
    std::fill(out, out + n, 1.0f);
    return;
  }
  const LookupConstants c(*this);
  float tx[ShadowReceivers::kCapacity], ty[ShadowReceivers::kCapacity], receiver[ShadowReceivers::kCapacity];
  int inside[ShadowReceivers::kCapacity];  // int, not bool: a bool array does not vectorise
  for (int k = 0; k < n; ++k)
    inside[k] = project_receiver(*this, c, points.px[k], points.py[k], points.pz[k], points.nx[k], points.ny[k],
                                 points.nz[k], tx[k], ty[k], receiver[k]);
  for (int k = 0; k < n; ++k) out[k] = inside[k] ? filter_taps(*this, tx[k], ty[k], receiver[k]) : 1.0f;
}

}  // namespace cr

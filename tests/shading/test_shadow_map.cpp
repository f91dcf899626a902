#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <optional>
#include <vector>

#include "engine/shading/shadow_map.h"

using namespace cr;

namespace {

// Distance along a ray (origin o, unit direction d) to its first hit, if any.
using Scene3 = std::function<std::optional<double>(const glm::dvec3& o, const glm::dvec3& d)>;

std::optional<double> hit_plane(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& point, const glm::dvec3& normal) {
  const double denom = glm::dot(d, normal);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double t = glm::dot(point - o, normal) / denom;
  return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}

std::optional<double> hit_box(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? std::optional<double>(t0) : std::nullopt;
}

std::optional<double> nearest(std::optional<double> a, std::optional<double> b) {
  if (!a) return b;
  if (!b) return a;
  return std::min(*a, *b);
}

// Renders the depth image analytically: for each texel centre, the ray from
// the map's sunward end (z = 1) to its far end (z = 0), depth = z of the first hit.
void render_depth(ShadowMap& map, const Scene3& scene) {
  const glm::dmat4 inv = glm::inverse(glm::dmat4(map.light_view_proj));
  for (int row = 0; row < map.size; ++row) {
    for (int col = 0; col < map.size; ++col) {
      const double x = (col + 0.5) / map.size * 2.0 - 1.0;
      const double y = 1.0 - (row + 0.5) / map.size * 2.0;
      const glm::dvec4 top = inv * glm::dvec4(x, y, 1.0, 1.0);
      const glm::dvec4 bottom = inv * glm::dvec4(x, y, 0.0, 1.0);
      const glm::dvec3 o = map.origin + glm::dvec3(top);
      const glm::dvec3 span = glm::dvec3(bottom) - glm::dvec3(top);
      const double length = glm::length(span);
      const std::optional<double> t = scene(o, span / length);
      float& depth = map.depth[size_t(row) * map.size + col];
      depth = (t && *t <= length) ? float(1.0 - *t / length) : 0.0f;
    }
  }
}

glm::vec3 sun_from(float elevation_deg, float azimuth_deg) {
  const float e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}

const Scene3 kGround = [](const glm::dvec3& o, const glm::dvec3& d) {
  return hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0));
};

bool inside_map(const ShadowMap& map, const glm::vec3& p, float margin) {
  const glm::vec4 c = map.light_view_proj * glm::vec4(glm::vec3(glm::dvec3(p) - map.origin), 1.0f);
  return std::abs(c.x) < 1.0f - margin && std::abs(c.y) < 1.0f - margin;
}

}  // namespace

TEST_CASE("shadow: a flat lit ground shows no acne at any sun elevation") {
  const Camera cam = Camera::look_at({0, 1.7, 0}, {8, 0, -10}, 1.0f, 16.0f / 9.0f, 0.1f);
  for (float elevation : {2.0f, 10.0f, 30.0f, 60.0f, 89.5f}) {
    for (int r : {0, 1, 2}) {
      CAPTURE(elevation);
      CAPTURE(r);
      ShadowMap map = fit_shadow_map(cam, sun_from(elevation, 37.0f), 40.0f, 256, r, {-200, 0, -200}, {200, 0, 200});
      render_depth(map, kGround);
      int tested = 0;
      float worst = 1.0f;
      for (float x = -40.0f; x <= 40.0f; x += 0.37f) {
        for (float z = -40.0f; z <= 40.0f; z += 0.41f) {
          const glm::vec3 p(x, 0.0f, z);
          if (!inside_map(map, p, 0.05f)) continue;
          ++tested;
          worst = std::min(worst, map.visibility(p, {0, 1, 0}));
        }
      }
      CHECK(tested > 1000);
      CHECK(worst == 1.0f);
    }
  }
}

TEST_CASE("shadow: a sloped lit plane shows no acne") {
  const Camera cam = Camera::look_at({0, 5, 10}, {0, 0, 0}, 1.0f, 1.5f, 0.1f);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(0.5, 1.0, 0.2));
  const Scene3 slope = [&](const glm::dvec3& o, const glm::dvec3& d) { return hit_plane(o, d, glm::dvec3(0.0), normal); };
  for (float elevation : {15.0f, 45.0f, 80.0f}) {
    ShadowMap map = fit_shadow_map(cam, sun_from(elevation, 200.0f), 30.0f, 256, 1, glm::vec3(-60.0f), glm::vec3(60.0f));
    if (glm::dot(glm::dvec3(map.direction_to_sun), normal) <= 0.05) continue;  // plane faces away: unlit anyway
    render_depth(map, slope);
    float worst = 1.0f;
    for (float a = -25.0f; a <= 25.0f; a += 0.53f) {
      for (float b = -25.0f; b <= 25.0f; b += 0.47f) {
        // A point on the plane: solve for y.
        const glm::vec3 p(a, float(-(normal.x * a + normal.z * b) / normal.y), b);
        if (!inside_map(map, p, 0.05f)) continue;
        worst = std::min(worst, map.visibility(p, glm::vec3(normal)));
      }
    }
    CAPTURE(elevation);
    CHECK(worst == 1.0f);
  }
}

TEST_CASE("shadow: a box on the ground - shadow starts at its foot, PCF edge, lit surroundings") {
  // Box [-1,1] x [0,2] x [-1,1]; sun 45 degrees up towards +X: the shadow
  // covers x in [-3, -1] on the ground, |z| <= 1.
  const Camera cam = Camera::look_at({-2, 3, 6}, {-1, 0, 0}, 1.0f, 1.0f, 0.1f);
  const glm::vec3 sun = sun_from(45.0f, 0.0f);
  ShadowMap map = fit_shadow_map(cam, sun, 12.0f, 1024, 1, {-50, 0, -50}, {50, 2, 50});
  const Scene3 scene = [](const glm::dvec3& o, const glm::dvec3& d) {
    return nearest(hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0)), hit_box(o, d, {-1, 0, -1}, {1, 2, 1}));
  };
  render_depth(map, scene);
  const float texel = map.texel_world_size;
  CHECK(texel < 0.05f);
  const glm::vec3 up(0, 1, 0);
  // No peter-panning: fully shadowed right at the box's foot and inside the shadow.
  CHECK(map.visibility({-1.0f - 0.25f * texel, 0.0f, 0.0f}, up) == 0.0f);
  CHECK(map.visibility({-1.0f - 2.0f * texel, 0.0f, 0.5f}, up) == 0.0f);
  CHECK(map.visibility({-2.0f, 0.0f, 0.0f}, up) == 0.0f);
  CHECK(map.visibility({-3.0f + 8.0f * texel, 0.0f, -1.0f + 8.0f * texel}, up) == 0.0f);
  // No acne on the lit parts: ground beside and beyond, the box top, its sunward wall.
  CHECK(map.visibility({-3.0f - 4.0f * texel, 0.0f, 0.0f}, up) == 1.0f);
  CHECK(map.visibility({0.0f, 0.0f, 1.0f + 4.0f * texel}, up) == 1.0f);
  CHECK(map.visibility({2.0f, 0.0f, 0.0f}, up) == 1.0f);
  CHECK(map.visibility({0.3f, 2.0f, -0.4f}, up) == 1.0f);
  CHECK(map.visibility({1.0f, 1.0f, 0.2f}, {1, 0, 0}) == 1.0f);
  CHECK(map.visibility({1.0f, 0.05f, 0.2f}, {1, 0, 0}) == 1.0f);
  // PCF: across the far edge (x = -3) visibility rises through fractional values.
  float previous = -1.0f;
  int fractional = 0;
  for (float x = -3.0f + 4.0f * texel; x >= -3.0f - 4.0f * texel; x -= 0.1f * texel) {
    const float v = map.visibility({x, 0.0f, 0.0f}, up);
    CHECK(v >= previous - 1e-6f);
    previous = v;
    if (v > 0.0f && v < 1.0f) ++fractional;
  }
  CHECK(previous == 1.0f);
  CHECK(fractional > 10);
}

TEST_CASE("shadow: a thin board standing on the ground - no peter-panning") {
  // A 2 cm board x in [-0.01, 0.01], 2 m tall, sun 30 degrees up towards +X:
  // near its foot the first surface the sun meets is the board's face just
  // above the ground, so any depth bias larger than the board's distance
  // along the light would detach the shadow from the foot.
  const Camera cam = Camera::look_at({-3, 2, 5}, {-1, 0, 0}, 1.0f, 1.0f, 0.1f);
  ShadowMap map = fit_shadow_map(cam, sun_from(30.0f, 0.0f), 12.0f, 1024, 1, {-50, 0, -50}, {50, 2, 50});
  const Scene3 scene = [](const glm::dvec3& o, const glm::dvec3& d) {
    return nearest(hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0)), hit_box(o, d, {-0.01, 0, -1}, {0.01, 2, 1}));
  };
  render_depth(map, scene);
  const float texel = map.texel_world_size;
  const glm::vec3 up(0, 1, 0);
  // Within the PCF footprint of the foot the kernel still sees the sunlit
  // ground in front of the board; from 4 texels behind it the shadow is full.
  CHECK(map.visibility({-0.01f - 1.0f * texel, 0.0f, 0.0f}, up) < 0.5f);
  for (float behind : {4.0f * texel, 8.0f * texel, 0.5f, 2.0f, 3.3f}) {
    CAPTURE(behind);
    CHECK(map.visibility({-0.01f - behind, 0.0f, 0.3f}, up) == 0.0f);
  }
  CHECK(map.visibility({-0.01f - 3.7f, 0.0f, 0.3f}, up) == 1.0f);  // beyond the 3.46 m shadow
  CHECK(map.visibility({0.01f + 2.0f * texel + 0.2f, 0.0f, 0.3f}, up) == 1.0f);  // sunny side
  CHECK(map.visibility({0.01f, 1.0f, 0.3f}, {1, 0, 0}) == 1.0f);                // sunlit face
}

TEST_CASE("shadow: a point under a hovering occluder is fully shadowed; outside the map is lit") {
  const Camera cam = Camera::look_at({0, 2, 8}, {0, 0, 0}, 1.0f, 1.0f, 0.1f);
  ShadowMap map = fit_shadow_map(cam, sun_from(80.0f, 120.0f), 20.0f, 512, 2, {-30, 0, -30}, {30, 3.2f, 30});
  const Scene3 scene = [](const glm::dvec3& o, const glm::dvec3& d) {
    return nearest(hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0)), hit_box(o, d, {-1, 3, -1}, {1, 3.2, 1}));
  };
  render_depth(map, scene);
  CHECK(map.visibility({0.0f, 0.0f, 0.0f}, {0, 1, 0}) == 0.0f);
  CHECK(map.visibility({0.0f, 1.5f, 0.0f}, {0, 0, 0}) == 0.0f);  // zero normal (fog): no offset
  CHECK(map.visibility({6.0f, 0.0f, 0.0f}, {0, 1, 0}) == 1.0f);
  // Beyond the map's extent, below its depth range, or far away: lit.
  CHECK(map.visibility({1000.0f, 0.0f, 0.0f}, {0, 1, 0}) == 1.0f);
  CHECK(map.visibility({0.0f, -1000.0f, 0.0f}, {0, 1, 0}) == 1.0f);
  // No shadow map at all: lit.
  CHECK(ShadowMap{}.visibility({0, 0, 0}, {0, 1, 0}) == 1.0f);
}

TEST_CASE("shadow: the fitted projection contains the view slice and the scene's casters") {
  const glm::vec3 scene_min(-500, -5, -500), scene_max(500, 120, 500);
  for (const glm::vec3& sun : {sun_from(30.0f, 10.0f), sun_from(89.9f, 0.0f), sun_from(5.0f, 250.0f)}) {
    const Camera cam = Camera::look_at({12.5, 3.0, -7.25}, {40, -2, 30}, 1.2f, 16.0f / 9.0f, 0.2f);
    const float distance = 80.0f;
    const ShadowMap map = fit_shadow_map(cam, sun, distance, 1024, 1, scene_min, scene_max);
    REQUIRE(map.size == 1024);
    REQUIRE(map.depth.size() == size_t(1024 * 1024));
    const float ty = std::tan(0.5f * cam.vfov_rad), tx = ty * cam.aspect;
    for (float d : {cam.znear, distance}) {
      for (float sx : {-1.0f, 1.0f}) {
        for (float sy : {-1.0f, 1.0f}) {
          const glm::dvec3 corner = cam.position + glm::dvec3(cam.forward * d + cam.right * (sx * d * tx) + cam.up * (sy * d * ty));
          const glm::vec4 c = map.light_view_proj * glm::vec4(glm::vec3(corner - map.origin), 1.0f);
          CHECK(std::abs(c.x) <= 1.0f);
          CHECK(std::abs(c.y) <= 1.0f);
          CHECK(c.z >= 0.0f);
          CHECK(c.z <= 1.0f);
        }
      }
    }
    // Every scene corner on the sun's side lies within the depth range (z <= 1).
    for (int i = 0; i < 8; ++i) {
      const glm::dvec3 corner((i & 1) ? scene_max.x : scene_min.x, (i & 2) ? scene_max.y : scene_min.y,
                              (i & 4) ? scene_max.z : scene_min.z);
      const glm::vec4 c = map.light_view_proj * glm::vec4(glm::vec3(corner - map.origin), 1.0f);
      CHECK(c.z <= 1.0f);
    }
    CHECK(glm::length(map.direction_to_sun) == doctest::Approx(1.0f));
    CHECK(map.depth_range > 0.0f);
  }
}

TEST_CASE("shadow: the fit is stable - rotation keeps the scale, translation moves whole texels") {
  const glm::vec3 sun = sun_from(35.0f, 60.0f);
  const glm::vec3 lo(-100.0f), hi(100.0f);
  const Camera a = Camera::look_at({3, 2, 1}, {10, 0, 4}, 1.0f, 1.6f, 0.1f);
  const Camera b = Camera::look_at({3, 2, 1}, {-7, 3, -9}, 1.0f, 1.6f, 0.1f);
  const ShadowMap ma = fit_shadow_map(a, sun, 50.0f, 512, 1, lo, hi);
  const ShadowMap mb = fit_shadow_map(b, sun, 50.0f, 512, 1, lo, hi);
  CHECK(ma.texel_world_size == mb.texel_world_size);
  CHECK(ma.light_view_proj[0][0] == mb.light_view_proj[0][0]);

  Camera c = a;
  c.position += glm::dvec3(0.123, 0.0, -0.071);
  const ShadowMap mc = fit_shadow_map(c, sun, 50.0f, 512, 1, lo, hi);
  // The same world point falls at the same sub-texel position in both maps.
  const glm::vec3 p(7.3f, 0.0f, 2.9f);
  auto texel_coord = [&](const ShadowMap& m) {
    const glm::vec4 clip = m.light_view_proj * glm::vec4(glm::vec3(glm::dvec3(p) - m.origin), 1.0f);
    return glm::vec2(clip.x, clip.y) * 0.5f * float(m.size);
  };
  const glm::vec2 ta = texel_coord(ma), tc = texel_coord(mc);
  const glm::vec2 shift = ta - tc;
  CHECK(std::abs(shift.x - std::round(shift.x)) < 1e-3f);
  CHECK(std::abs(shift.y - std::round(shift.y)) < 1e-3f);
  CHECK(fit_shadow_map(a, sun, 50.0f, 0, 1, lo, hi).size == 0);
}

TEST_CASE("shadow: the batched lookup returns each point's own visibility, bit for bit") {
  // Points over a box's shadow, its penumbra, lit ground, tilted normals,
  // zero normals and points off the map, in one batch.
  const Camera cam = Camera::look_at({-2, 3, 6}, {-1, 0, 0}, 1.0f, 1.0f, 0.1f);
  for (int radius : {0, 1, 2}) {
    ShadowMap map = fit_shadow_map(cam, sun_from(45.0f, 10.0f), 12.0f, 512, radius, {-50, 0, -50}, {50, 2, 50});
    render_depth(map, [](const glm::dvec3& o, const glm::dvec3& d) {
      return nearest(hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0)), hit_box(o, d, {-1, 0, -1}, {1, 2, 1}));
    });
    ShadowReceivers points;
    std::vector<glm::vec3> position, normal;
    for (int k = 0; k < ShadowReceivers::kCapacity; ++k) {
      const float t = float(k) / float(ShadowReceivers::kCapacity - 1);
      position.push_back(k % 9 == 8 ? glm::vec3(500.0f, 0.0f, 3.0f) : glm::vec3(-4.0f + 4.0f * t, 0.0f, 0.37f * t));
      normal.push_back(k % 7 == 6 ? glm::vec3(0.0f) : glm::normalize(glm::vec3(0.3f * std::sin(float(k)), 1.0f, 0.2f)));
      points.px[k] = position[k].x;
      points.py[k] = position[k].y;
      points.pz[k] = position[k].z;
      points.nx[k] = normal[k].x;
      points.ny[k] = normal[k].y;
      points.nz[k] = normal[k].z;
    }
    points.count = ShadowReceivers::kCapacity;
    float batched[ShadowReceivers::kCapacity];
    map.visibility(points, batched);
    int fractional = 0, outside = 0;
    for (int k = 0; k < points.count; ++k) {
      CHECK(batched[k] == map.visibility(position[k], normal[k]));
      fractional += batched[k] > 0.0f && batched[k] < 1.0f;
      outside += !inside_map(map, position[k], 0.0f);
    }
    CHECK(fractional > 0);
    CHECK(outside > 0);
  }
  // No map: everything lit.
  ShadowReceivers one;
  one.count = 1;
  float v = 0.0f;
  ShadowMap{}.visibility(one, &v);
  CHECK(v == 1.0f);
}

namespace {

// ShadowMap::visibility as shadow_map.cpp defines it, written out plainly: the
// biased receiver projected with glm, then the PCF weighted sum over every
// tap (no all-lit/all-shadowed shortcut, no row-wise compares).
// `footprint_crosses_border` tells whether some tap lies off the map.
float reference_visibility(const ShadowMap& map, const glm::vec3& p, const glm::vec3& normal,
                           bool& footprint_crosses_border) {
  footprint_crosses_border = false;
  const int r = map.pcf_radius;
  const float cos_theta = std::clamp(glm::dot(normal, map.direction_to_sun), -1.0f, 1.0f);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  const float offset = 1.5f * float(r + 1) * map.texel_world_size * sin_theta;
  const glm::vec3 rel(float(double(p.x) - map.origin.x + double(normal.x * offset)),
                      float(double(p.y) - map.origin.y + double(normal.y * offset)),
                      float(double(p.z) - map.origin.z + double(normal.z * offset)));
  const glm::vec4 clip = map.light_view_proj * glm::vec4(rel, 1.0f);
  if (!(std::abs(clip.x) <= 1.0f && std::abs(clip.y) <= 1.0f && clip.z >= 0.0f && clip.z <= 1.0f)) return 1.0f;
  const float receiver = clip.z + 0.5f * map.texel_world_size / map.depth_range + 1.0f / float(1 << 20);
  const float tx = (clip.x * 0.5f + 0.5f) * float(map.size) - 0.5f;
  const float ty = (0.5f - clip.y * 0.5f) * float(map.size) - 0.5f;
  const int x0 = int(std::floor(tx)), y0 = int(std::floor(ty));
  const float ax = tx - float(x0), ay = ty - float(y0);
  float lit = 0.0f, shadowed = 0.0f;
  for (int dy = -r; dy <= r + 1; ++dy) {
    for (int dx = -r; dx <= r + 1; ++dx) {
      const float wx = dx == -r ? 1.0f - ax : (dx == r + 1 ? ax : 1.0f);
      const float wy = dy == -r ? 1.0f - ay : (dy == r + 1 ? ay : 1.0f);
      const int x = x0 + dx, y = y0 + dy;
      const bool in_map = x >= 0 && y >= 0 && x < map.size && y < map.size;
      footprint_crosses_border |= !in_map;
      if (!in_map || map.depth[size_t(y) * size_t(map.size) + size_t(x)] <= receiver)
        lit += wx * wy;
      else
        shadowed += wx * wy;
    }
  }
  if (!(shadowed > 0.0f)) return 1.0f;
  if (!(lit > 0.0f)) return 0.0f;
  return lit / (lit + shadowed);
}

}  // namespace

TEST_CASE("shadow: visibility equals the plain PCF definition, bit for bit, at every filter radius") {
  // A box's shadow (all-shadowed footprints), its penumbra, lit ground, tilted
  // normals, and points over the map's border and beyond it, on a small map.
  // Radius 1 takes the unrolled 4x4 compare, the others the general one.
  const Camera cam = Camera::look_at({-2, 3, 6}, {-1, 0, 0}, 1.0f, 1.0f, 0.1f);
  for (int radius : {0, 1, 2, 3}) {
    CAPTURE(radius);
    ShadowMap map = fit_shadow_map(cam, sun_from(30.0f, 15.0f), 12.0f, 128, radius, {-50, 0, -50}, {50, 2, 50});
    render_depth(map, [](const glm::dvec3& o, const glm::dvec3& d) {
      return nearest(hit_plane(o, d, glm::dvec3(0.0), glm::dvec3(0, 1, 0)),
                     hit_box(o, d, {-1.5, 0, -1.5}, {1.5, 2, 1.5}));
    });
    int differing = 0, lit = 0, shadowed = 0, penumbra = 0, border = 0;
    ShadowReceivers batch;
    std::vector<float> expected;
    float batched[ShadowReceivers::kCapacity];
    int batch_differing = 0;
    for (float x = -30.0f; x <= 30.0f; x += 0.131f) {
      for (float z = -30.0f; z <= 30.0f; z += 0.173f) {
        const glm::vec3 p(x, 0.0f, z);
        const glm::vec3 n = glm::normalize(glm::vec3(0.2f * std::sin(3.0f * x), 1.0f, 0.15f * std::cos(2.0f * z)));
        bool crosses = false;
        const float want = reference_visibility(map, p, n, crosses);
        const float got = map.visibility(p, n);
        differing += std::memcmp(&got, &want, sizeof(float)) != 0;
        lit += want == 1.0f;
        shadowed += want == 0.0f;
        penumbra += want > 0.0f && want < 1.0f;
        border += crosses;
        // The batched lookup, in batches of kCapacity points.
        const int k = batch.count++;
        batch.px[k] = p.x, batch.py[k] = p.y, batch.pz[k] = p.z;
        batch.nx[k] = n.x, batch.ny[k] = n.y, batch.nz[k] = n.z;
        expected.push_back(want);
        if (batch.count == ShadowReceivers::kCapacity) {
          map.visibility(batch, batched);
          batch_differing += std::memcmp(batched, expected.data(), sizeof(batched)) != 0;
          batch.count = 0;
          expected.clear();
        }
      }
    }
    CHECK(differing == 0);
    CHECK(batch_differing == 0);
    CHECK(lit > 1000);
    CHECK(shadowed > 100);
    CHECK(penumbra > 100);
    CHECK(border > 10);
  }
}

// composite_fog against its definition, lookup_fog per pixel: the same bits
// for sky, geometry in every slice (boundaries, first and last slice
// included), pixels at or in front of the near plane and without distance,
// runs of only sky and of only such pixels, for tile rectangles and for rows
// wider than one tile; for the float volume and the fixed-point one (decoded
// as it is read).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "fog/froxel_passes.h"

using namespace cr;

namespace {

struct CompositeScene {
  FroxelGrid grid{77, 29, 8, 16, 0.1f, 20.0f, 0.3f};
  std::vector<IntegratedFroxel> volume;
  std::vector<FixedIntegratedFroxel> fixed_volume;
  std::vector<float> distance;
  std::vector<glm::vec3> color;
};

CompositeScene make_scene() {
  CompositeScene s;
  std::mt19937 rng(7);
  auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
  s.volume.resize(s.grid.count());
  for (IntegratedFroxel& f : s.volume) {
    f.in_scatter = glm::vec3(uniform(0, 2), uniform(0, 2), uniform(0, 2));
    f.transmittance = uniform(0.05f, 1);
    // Clear air, optically thin (the opacity's series) and thick froxels.
    const int kind = int(rng() % 3);
    f.extinction = kind == 0 ? 0.0f : kind == 1 ? uniform(0, 1e-3f) : uniform(0, 3);
  }
  const FroxelGrid& g = s.grid;
  const float inf = std::numeric_limits<float>::infinity();
  const int w = g.width(), h = g.height();
  s.distance.resize(size_t(w) * h);
  s.color.resize(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float d;
      const int run = (x + 4) / 8;  // the runs of a row (froxel centres at 8 i + 4)
      if (y % 3 == 1 && run % 3 != 0) {
        d = run % 3 == 1 ? inf : 0.0f;  // whole runs of sky and of no fog
      } else if (y % 3 == 0) {
        d = g.near_distance() + 0.02f * float(x + 7 * y);  // a smooth surface: runs share slices
      } else {
        const int k = int(rng() % unsigned(g.nz()));
        switch (rng() % 12) {
          case 0: d = std::numeric_limits<float>::quiet_NaN(); break;
          case 1: d = 0.0f; break;
          case 2: d = g.near_distance(); break;
          case 3: d = std::nextafter(g.near_distance(), inf); break;
          case 4: d = g.boundary(k); break;
          case 5: d = std::nextafter(g.boundary(k + 1), 0.0f); break;
          case 6: d = g.far_distance(); break;
          case 7: d = inf; break;
          case 8: d = 1e30f; break;
          default: d = uniform(g.near_distance(), g.far_distance()); break;
        }
      }
      s.distance[size_t(y) * w + x] = d;
      s.color[size_t(y) * w + x] = glm::vec3(uniform(0, 5), uniform(0, 5), uniform(0, 5));
    }
  // Fixed point: radiance codes up to hdr16's top, depth codes that grow
  // along each column by nothing (clear air), a little or a lot, saturating.
  s.fixed_volume.resize(s.grid.count());
  for (size_t c = 0; c < s.grid.columns(); ++c) {
    uint32_t depth = 0;
    for (int k = 0; k < s.grid.nz(); ++k) {
      FixedIntegratedFroxel& f = s.fixed_volume[c * size_t(s.grid.nz()) + size_t(k)];
      for (uint16_t& code : f.in_scatter) code = uint16_t(rng() % 0x10000);
      const int kind = int(rng() % 3);
      depth = std::min<uint32_t>(depth + (kind == 0 ? 0u : kind == 1 ? rng() % 8 : rng() % 8000), 0xFFFF);
      f.optical_depth = uint16_t(depth);
    }
  }
  return s;
}

// Pixels of [x0, x1) x [y0, y1) become colour * T + L of lookup_fog where
// beyond the near plane; every other pixel keeps its colour.
template <class Volume>
std::vector<glm::vec3> expected(const CompositeScene& s, const Volume& volume, int x0, int y0, int x1, int y1) {
  std::vector<glm::vec3> out = s.color;
  const int w = s.grid.width();
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!(s.distance[i] > s.grid.near_distance())) continue;
      glm::vec3 l;
      float t;
      lookup_fog(s.grid, volume, float(x) + 0.5f, float(y) + 0.5f, s.distance[i], l, t);
      out[i] = out[i] * t + l;
    }
  return out;
}

int bit_mismatches(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  int bad = 0;
  for (size_t i = 0; i < a.size(); ++i) bad += std::memcmp(&a[i], &b[i], sizeof(glm::vec3)) != 0;
  return bad;
}

template <class Volume>
void check_composite(const CompositeScene& s, const Volume& volume) {
  const int w = s.grid.width(), h = s.grid.height();
  const std::vector<glm::vec3> all = expected(s, volume, 0, 0, w, h);
  std::vector<glm::vec3> tiled = s.color;
  for (int y0 = 0; y0 < h; y0 += 16)
    for (int x0 = 0; x0 < w; x0 += 16)
      composite_fog(s.grid, volume, s.distance, tiled, w, x0, y0, std::min(w, x0 + 16), std::min(h, y0 + 16));
  CHECK(bit_mismatches(tiled, all) == 0);
  // Rows wider than one band.
  std::vector<glm::vec3> whole = s.color;
  composite_fog(s.grid, volume, s.distance, whole, w, 0, 0, w, h);
  CHECK(bit_mismatches(whole, all) == 0);
  // A rectangle that cuts runs at both ends; nothing outside it changes.
  std::vector<glm::vec3> part = s.color;
  composite_fog(s.grid, volume, s.distance, part, w, 5, 3, 70, 20);
  CHECK(bit_mismatches(part, expected(s, volume, 5, 3, 70, 20)) == 0);
}

template <class Volume>
void check_fragments(const CompositeScene& s, const Volume& volume) {
  const int w = s.grid.width(), h = s.grid.height();
  std::vector<glm::vec3> pixels = s.color;
  composite_fog(s.grid, volume, s.distance, pixels, w, 0, 0, w, h);
  std::vector<EdgeFragment> fragments;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      EdgeFragment f;
      f.pixel = uint32_t(i);
      f.x = float(x) + 0.5f;
      f.y = float(y) + 0.5f;
      f.distance = s.distance[i];
      f.color = s.color[i];
      fragments.push_back(f);
    }
  composite_fog_fragments(s.grid, volume, fragments);
  int bad = 0;
  for (const EdgeFragment& f : fragments) bad += std::memcmp(&f.color, &pixels[f.pixel], sizeof(glm::vec3)) != 0;
  CHECK(bad == 0);
  // Off-centre: the lookup at the fragment's own position, not its pixel's.
  EdgeFragment f;
  f.x = 100.3f;
  f.y = 77.9f;
  f.distance = 0.5f * (s.grid.near_distance() + s.grid.far_distance());
  f.color = glm::vec3(1.0f);
  glm::vec3 l;
  float t;
  lookup_fog(s.grid, volume, f.x, f.y, f.distance, l, t);
  composite_fog_fragments(s.grid, volume, std::span(&f, 1));
  CHECK(f.color == glm::vec3(1.0f) * t + l);
  CHECK(t < 1.0f);
}

}  // namespace

TEST_CASE("composite_fog gives lookup_fog's bits for every pixel, per tile and per whole row, at both precisions") {
  const CompositeScene s = make_scene();
  check_composite(s, s.volume);
  check_composite(s, s.fixed_volume);
}

TEST_CASE("edge-pixel fragments at pixel centres get composite_fog's bits; elsewhere their own position's lookup") {
  const CompositeScene s = make_scene();
  check_fragments(s, s.volume);
  check_fragments(s, s.fixed_volume);
}

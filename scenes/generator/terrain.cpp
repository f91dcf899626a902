#include "scenes/generator/terrain.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "scenes/generator/noise.h"

namespace cr::gen {

namespace {

constexpr double kUnit = 2.0;          // metres per finest cell
constexpr int kPatchCells = 8;         // cells along a quadtree patch side
constexpr int kRootLevel = 13;         // root patch: 8 * 2^13 units = 131 km
constexpr int32_t kHalfUnits = kPatchCells << (kRootLevel - 1);
constexpr double kGroundTile = 8.0;    // metres per repeat of the ground texture
// LOD is centred between the default camera and the far end of the village.
constexpr double kLodCentreX = 0.0;
constexpr double kLodCentreZ = -40.0;

struct NodeKey {
  int level;
  int32_t i, j;  // patch index at this level, from the root's corner
  auto operator<=>(const NodeKey&) const = default;
};

int32_t patch_units(int level) { return kPatchCells << level; }
// World metres of a lattice point given in units from the root's corner.
double to_metres(int32_t u) { return static_cast<double>(u - kHalfUnits) * kUnit; }

double distance_to_patch(const NodeKey& n) {
  const int32_t size = patch_units(n.level);
  const double x0 = to_metres(n.i * size), x1 = to_metres((n.i + 1) * size);
  const double z0 = to_metres(n.j * size), z1 = to_metres((n.j + 1) * size);
  const double dx = std::max({x0 - kLodCentreX, 0.0, kLodCentreX - x1});
  const double dz = std::max({z0 - kLodCentreZ, 0.0, kLodCentreZ - z1});
  return std::sqrt(dx * dx + dz * dz);
}

// Largest height difference between the surface and this patch's bilinear
// cells, sampled at cell centres and edge midpoints: the error of not splitting.
double patch_error(const NodeKey& n) {
  const int32_t s = 1 << n.level;
  const int32_t ox = n.i * patch_units(n.level), oz = n.j * patch_units(n.level);
  std::array<std::array<double, kPatchCells + 1>, kPatchCells + 1> h{};
  for (int b = 0; b <= kPatchCells; ++b)
    for (int a = 0; a <= kPatchCells; ++a)
      h[b][a] = terrain_height(to_metres(ox + a * s), to_metres(oz + b * s));
  const double half = 0.5 * s;
  double error = 0.0;
  for (int b = 0; b < kPatchCells; ++b) {
    for (int a = 0; a < kPatchCells; ++a) {
      const double x = to_metres(ox + a * s), z = to_metres(oz + b * s);
      const double hm = kUnit * half;
      const double centre = 0.25 * (h[b][a] + h[b][a + 1] + h[b + 1][a] + h[b + 1][a + 1]);
      error = std::max(error, std::abs(terrain_height(x + hm, z + hm) - centre));
      error = std::max(error, std::abs(terrain_height(x + hm, z) - 0.5 * (h[b][a] + h[b][a + 1])));
      error = std::max(error, std::abs(terrain_height(x, z + hm) - 0.5 * (h[b][a] + h[b + 1][a])));
    }
  }
  return error;
}

bool needs_split(const NodeKey& n, int detail) {
  if (n.level == 0) return false;
  const double spacing = kUnit * (1 << n.level);
  const double distance = std::max(distance_to_patch(n), 1.0);
  // Cells no wider than distance / (6 * detail) keep silhouettes and shading
  // smooth everywhere. Rough land (the mountains) is refined further while its
  // height error exceeds ~4 px at 720p / detail, down to distance / (32 * detail)
  // so that the range does not eat the triangle budget.
  if (spacing * 6.0 * detail > distance) return true;
  if (spacing * 32.0 * detail <= distance) return false;
  return patch_error(n) / distance > 0.006 / detail;
}

class Quadtree {
 public:
  explicit Quadtree(int detail) {
    build({kRootLevel, 0, 0}, detail);
    balance();
  }
  const std::set<NodeKey>& leaves() const { return leaves_; }
  bool is_internal(const NodeKey& n) const { return internal_.count(n) != 0; }

 private:
  static std::array<NodeKey, 4> children(const NodeKey& n) {
    const int l = n.level - 1;
    return {NodeKey{l, 2 * n.i, 2 * n.j}, NodeKey{l, 2 * n.i + 1, 2 * n.j},
            NodeKey{l, 2 * n.i, 2 * n.j + 1}, NodeKey{l, 2 * n.i + 1, 2 * n.j + 1}};
  }

  void build(const NodeKey& n, int detail) {
    if (!needs_split(n, detail)) {
      leaves_.insert(n);
      return;
    }
    internal_.insert(n);
    for (const NodeKey& c : children(n)) build(c, detail);
  }

  // A leaf more than one level coarser than a neighbour would need more than
  // one midpoint per cell edge: split such leaves until neighbours differ by <= 1.
  bool too_coarse(const NodeKey& n) const {
    constexpr std::array<std::array<int, 2>, 4> sides{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};
    for (const auto& [di, dj] : sides) {
      const NodeKey neighbour{n.level, n.i + di, n.j + dj};
      if (!is_internal(neighbour)) continue;
      for (const NodeKey& c : children(neighbour)) {
        const bool touches = (di == 1 && c.i == 2 * neighbour.i) || (di == -1 && c.i == 2 * neighbour.i + 1) ||
                             (dj == 1 && c.j == 2 * neighbour.j) || (dj == -1 && c.j == 2 * neighbour.j + 1);
        if (touches && is_internal(c)) return true;
      }
    }
    return false;
  }

  void balance() {
    for (;;) {
      std::vector<NodeKey> split;
      for (const NodeKey& n : leaves_)
        if (too_coarse(n)) split.push_back(n);
      if (split.empty()) return;
      for (const NodeKey& n : split) {
        leaves_.erase(n);
        internal_.insert(n);
        for (const NodeKey& c : children(n)) leaves_.insert(c);
      }
    }
  }

  std::set<NodeKey> leaves_;
  std::set<NodeKey> internal_;
};

glm::vec3 blend(const glm::vec3& a, const glm::vec3& b, double t) {
  return a + (b - a) * static_cast<float>(t);
}

// Albedo of far terrain: grass on lowlands, rock on steep or high ground,
// snow on high gentle slopes; noise breaks up the altitude bands.
glm::vec3 far_albedo(double x, double z, double height, double normal_y, const glm::vec3& grass) {
  const glm::vec3 forest{0.035f, 0.060f, 0.025f};
  const glm::vec3 rock{0.20f, 0.185f, 0.165f};
  const glm::vec3 snow{0.80f, 0.82f, 0.86f};
  const double n = fbm(x / 700.0, z / 700.0, 71u, 3) - 0.5;
  const double forest_w = smoothstep(120.0, 450.0, height + 300.0 * n) * (1.0 - smoothstep(1100.0, 1400.0, height));
  const double rock_w = std::max(smoothstep(0.85, 0.6, normal_y), smoothstep(1000.0, 1500.0, height + 400.0 * n));
  const double snow_w = smoothstep(1450.0, 1800.0, height + 500.0 * n) * smoothstep(0.5, 0.75, normal_y);
  return blend(blend(blend(grass, forest, forest_w), rock, rock_w), snow, snow_w);
}

class ChunkBuilder {
 public:
  ChunkBuilder(bool far, const glm::vec3& grass) : far_(far), grass_(grass) {}

  void add_patch(const NodeKey& n, const std::array<bool, 4>& finer_side) {
    const int32_t s = 1 << n.level;
    const int32_t ox = n.i * patch_units(n.level), oz = n.j * patch_units(n.level);
    for (int b = 0; b < kPatchCells; ++b) {
      for (int a = 0; a < kPatchCells; ++a) {
        const int32_t x0 = ox + a * s, x1 = x0 + s, z0 = oz + b * s, z1 = z0 + s;
        // Edge midpoints where the neighbouring patch is finer: +x, -x, +z, -z.
        const bool mx1 = finer_side[0] && a == kPatchCells - 1;
        const bool mx0 = finer_side[1] && a == 0;
        const bool mz1 = finer_side[2] && b == kPatchCells - 1;
        const bool mz0 = finer_side[3] && b == 0;
        const uint32_t c00 = vertex(x0, z0), c10 = vertex(x1, z0);
        const uint32_t c11 = vertex(x1, z1), c01 = vertex(x0, z1);
        if (!(mx1 || mx0 || mz1 || mz0)) {
          triangle(x0, z0, c00, x0, z1, c01, x1, z1, c11);
          triangle(x0, z0, c00, x1, z1, c11, x1, z0, c10);
          continue;
        }
        // Fan around the cell centre through corners and midpoints in order.
        const int32_t h = s / 2;
        struct Point { int32_t x, z; };
        std::vector<Point> ring{{x0, z0}};
        if (mz0) ring.push_back({x0 + h, z0});
        ring.push_back({x1, z0});
        if (mx1) ring.push_back({x1, z0 + h});
        ring.push_back({x1, z1});
        if (mz1) ring.push_back({x0 + h, z1});
        ring.push_back({x0, z1});
        if (mx0) ring.push_back({x0, z0 + h});
        const int32_t cx = x0 + h, cz = z0 + h;
        const uint32_t centre = vertex(cx, cz);
        for (size_t k = 0; k < ring.size(); ++k) {
          const Point& p = ring[k];
          const Point& q = ring[(k + 1) % ring.size()];
          triangle(cx, cz, centre, p.x, p.z, vertex(p.x, p.z), q.x, q.z, vertex(q.x, q.z));
        }
      }
    }
  }

  TerrainChunk take() { return {std::move(mesh_), far_}; }

 private:
  uint32_t vertex(int32_t ux, int32_t uz) {
    const auto [it, inserted] = index_.try_emplace({ux, uz}, static_cast<uint32_t>(mesh_.positions.size()));
    if (!inserted) return it->second;
    const double x = to_metres(ux), z = to_metres(uz);
    const double y = terrain_height(x, z);
    // The normal's difference step depends on position only, so a vertex
    // shared by two chunks gets the same normal in both.
    const double dx = x - kLodCentreX, dz = z - kLodCentreZ;
    const double e = std::clamp(std::sqrt(dx * dx + dz * dz) / 48.0, 1.0, 300.0);
    const double gx = (terrain_height(x + e, z) - terrain_height(x - e, z)) / (2.0 * e);
    const double gz = (terrain_height(x, z + e) - terrain_height(x, z - e)) / (2.0 * e);
    const glm::dvec3 normal = glm::normalize(glm::dvec3(-gx, 1.0, -gz));
    mesh_.positions.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    mesh_.normals.emplace_back(normal);
    mesh_.uvs.emplace_back(static_cast<float>(x / kGroundTile), static_cast<float>(z / kGroundTile));
    if (far_) mesh_.colors.emplace_back(far_albedo(x, z, y, normal.y, grass_), 1.0f);
    return it->second;
  }

  // Emits a triangle facing +Y (counter-clockwise seen from above).
  void triangle(int32_t ax, int32_t az, uint32_t a, int32_t bx, int32_t bz, uint32_t b, int32_t cx, int32_t cz,
                uint32_t c) {
    const int64_t cross_y = int64_t(bz - az) * (cx - ax) - int64_t(bx - ax) * (cz - az);
    if (cross_y > 0) {
      mesh_.indices.insert(mesh_.indices.end(), {a, b, c});
    } else {
      mesh_.indices.insert(mesh_.indices.end(), {a, c, b});
    }
  }

  bool far_;
  glm::vec3 grass_;
  MeshData mesh_;
  std::map<std::pair<int32_t, int32_t>, uint32_t> index_;
};

}  // namespace

double terrain_height(double x, double z) {
  // Rolling hills (350 m wavelength), calmed around the village.
  const double vx = x, vz = z + 60.0;
  const double village = smoothstep(150.0, 450.0, std::sqrt(vx * vx + vz * vz));
  const double hills = (fbm(x / 350.0, z / 350.0, 11u, 5) - 0.5) * 40.0 * (0.2 + 0.8 * village);
  // Broad undulation of the plains, growing in beyond the first kilometre.
  const double r = std::sqrt(x * x + z * z);
  const double plains = (fbm(x / 4000.0, z / 4000.0, 23u, 4) - 0.5) * 160.0 * smoothstep(500.0, 3000.0, r);
  // The mountain range: a band from 12 to 52 km towards -Z.
  const double band = smoothstep(-9000.0, -18000.0, z) * (1.0 - smoothstep(-46000.0, -56000.0, z));
  double mountains = 0.0;
  if (band > 0.0) {
    const double ridges = ridged_fbm(x / 9000.0, z / 9000.0, 37u, 5);
    const double massif = fbm(x / 20000.0, z / 20000.0, 41u, 2);
    mountains = band * (200.0 + 2800.0 * ridges * ridges * (0.4 + 0.9 * massif));
  }
  return hills + plains + mountains;
}

std::vector<TerrainChunk> build_terrain(int detail, const glm::vec3& near_albedo) {
  const Quadtree tree(detail);
  // Group the leaves of one level under a common ancestor two levels up.
  std::map<NodeKey, std::vector<NodeKey>> groups;
  for (const NodeKey& n : tree.leaves()) groups[{n.level, n.i >> 2, n.j >> 2}].push_back(n);
  std::vector<TerrainChunk> chunks;
  for (const auto& [group, members] : groups) {
    const bool far = distance_to_patch({group.level + 2, group.i, group.j}) > 3000.0;
    ChunkBuilder builder(far, near_albedo);
    for (const NodeKey& n : members) {
      const std::array<bool, 4> finer{tree.is_internal({n.level, n.i + 1, n.j}), tree.is_internal({n.level, n.i - 1, n.j}),
                                      tree.is_internal({n.level, n.i, n.j + 1}), tree.is_internal({n.level, n.i, n.j - 1})};
      builder.add_patch(n, finer);
    }
    chunks.push_back(builder.take());
  }
  return chunks;
}

}  // namespace cr::gen

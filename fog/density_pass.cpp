// fog.density: voxelisation of the medium into the froxel grid (HDRP's
// "clear + height fog" and "fog volume" passes in one) along each column's
// centre ray: the height fog at the slice centre, and where volumes lie the
// mean over stratified points of the slice (see DensityPlan). A froxel's
// value depends only on the medium, never on the footprints, which only
// bound the work: culling is exact.
#include <algorithm>
#include <cmath>

#include "fog/froxel_passes.h"

namespace cr {

FroxelView make_froxel_view(const FroxelGrid& grid, const Camera& camera, JobSystem& jobs) {
  FroxelView v;
  v.grid = grid;
  v.camera = camera;
  v.directions.resize(grid.columns());
  v.active_slices.assign(grid.columns(), uint16_t(grid.nz()));
  v.lit_slices.assign(grid.columns(), uint16_t(grid.nz()));
  // PixelRays::direction at each column centre, with the x term from a
  // per-column table (the same operations, so the same bits).
  const int nx = grid.nx();
  const PixelRays rays(camera, grid.width(), grid.height());
  std::vector<float> screen_x(static_cast<size_t>(nx));
  for (int x = 0; x < nx; ++x) screen_x[size_t(x)] = rays.screen_x(grid.column_center_px(x, 0).x);
  jobs.parallel_for("fog.columns", size_t(grid.ny()), 8, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y) {
      const float sy = rays.screen_y(grid.column_center_px(0, int(y)).y);
      glm::vec3* out = v.directions.data() + y * size_t(nx);
      for (int x = 0; x < nx; ++x) out[x] = rays.through(screen_x[size_t(x)], sy);
    }
  });
  return v;
}

std::vector<VolumeFootprint> volume_footprints(const FroxelView& view, const FogMedium& medium) {
  const FroxelGrid& g = view.grid;
  const Camera& cam = view.camera;
  const float tan_y = std::tan(0.5f * cam.vfov_rad);
  const float tan_x = tan_y * cam.aspect;
  const float s = float(g.froxel_size());
  // No froxel point lies nearer than the near distance along a ray through
  // the screen, so none has a view depth below that distance times the
  // cosine of the screen corner's ray (1% kept as margin). The boxes are
  // clipped at this depth: what lies in front of it projects to a bounded
  // rectangle, even for a box that reaches behind the camera.
  const float z_clip = 0.99f * g.near_distance() / std::sqrt(1.0f + tan_x * tan_x + tan_y * tan_y);
  std::vector<VolumeFootprint> out;
  const auto& volumes = medium.volumes();
  for (size_t i = 0; i < volumes.size(); ++i) {
    const PlacedFogVolume& v = volumes[i];
    // Distance from the camera to the box (0 inside) and to its farthest corner.
    const glm::vec3 local(glm::dot(-v.center, v.axes[0]), glm::dot(-v.center, v.axes[1]),
                          glm::dot(-v.center, v.axes[2]));
    const float d_min = glm::length(glm::max(glm::abs(local) - v.half_size, glm::vec3(0.0f)));
    glm::vec3 corner[8];
    float z[8];
    float d_max = 0.0f;
    for (int c = 0; c < 8; ++c) {
      corner[c] = v.center + v.axes[0] * ((c & 1) ? v.half_size.x : -v.half_size.x) +
                  v.axes[1] * ((c & 2) ? v.half_size.y : -v.half_size.y) +
                  v.axes[2] * ((c & 4) ? v.half_size.z : -v.half_size.z);
      z[c] = glm::dot(corner[c], cam.forward);
      d_max = std::max(d_max, glm::length(corner[c]));
    }
    if (d_min > g.far_distance() || d_max < g.near_distance()) continue;
    // Screen bounds of the box clipped at z_clip: its corners in front, and
    // where its 12 edges cross the clip plane.
    float px_min = 1e30f, px_max = -1e30f, py_min = 1e30f, py_max = -1e30f;
    auto include = [&](const glm::vec3& p, float pz) {
      const float px = (glm::dot(p, cam.right) / (pz * tan_x) * 0.5f + 0.5f) * float(g.width());
      const float py = (0.5f - glm::dot(p, cam.up) / (pz * tan_y) * 0.5f) * float(g.height());
      px_min = std::min(px_min, px);
      px_max = std::max(px_max, px);
      py_min = std::min(py_min, py);
      py_max = std::max(py_max, py);
    };
    bool any = false;
    for (int c = 0; c < 8; ++c) {
      if (z[c] >= z_clip) {
        include(corner[c], z[c]);
        any = true;
      }
      for (int axis = 1; axis < 8; axis <<= 1) {  // each edge once, from its lower corner
        const int e = c | axis;
        if ((c & axis) || (z[c] >= z_clip) == (z[e] >= z_clip)) continue;
        const float a = (z_clip - z[c]) / (z[e] - z[c]);
        include(corner[c] + (corner[e] - corner[c]) * a, z_clip);
      }
    }
    if (!any) continue;  // wholly behind the clip plane (no edge crosses it either)
    if (px_max < 0.0f || py_max < 0.0f || px_min > float(g.nx()) * s || py_min > float(g.ny()) * s) continue;
    VolumeFootprint f;
    f.volume = int(i);
    f.x0 = std::clamp(int(std::floor(px_min / s)), 0, g.nx() - 1);
    f.x1 = std::clamp(int(std::floor(px_max / s)), 0, g.nx() - 1);
    f.y0 = std::clamp(int(std::floor(py_min / s)), 0, g.ny() - 1);
    f.y1 = std::clamp(int(std::floor(py_max / s)), 0, g.ny() - 1);
    f.k0 = std::clamp(int(std::floor(g.slice_coord(d_min))), 0, g.nz() - 1);
    f.k1 = std::clamp(int(std::floor(g.slice_coord(d_max))), 0, g.nz() - 1);
    out.push_back(f);
  }
  return out;
}

DensityPlan plan_density(const FroxelView& view, const FogMedium& medium, int samples) {
  const FroxelGrid& g = view.grid;
  DensityPlan plan;
  plan.footprints = volume_footprints(view, medium);
  plan.samples = std::max(samples, 1);
  plan.centers.resize(size_t(g.nz()));
  plan.sample_t.resize(size_t(g.nz()) * size_t(plan.samples));
  for (int k = 0; k < g.nz(); ++k) {
    plan.centers[size_t(k)] = g.center(k);
    for (int s = 0; s < plan.samples; ++s)
      plan.sample_t[size_t(k) * plan.samples + size_t(s)] =
          g.boundary(k) + g.thickness(k) * ((float(s) + 0.5f) / float(plan.samples));
  }
  plan.stats.visible_volumes = int(plan.footprints.size());
  for (const VolumeFootprint& f : plan.footprints)
    plan.stats.volume_froxels += size_t(f.x1 - f.x0 + 1) * size_t(f.y1 - f.y0 + 1) * size_t(f.k1 - f.k0 + 1);
  return plan;
}

void voxelize_rows(const FroxelView& view, const FogMedium& medium, const DensityPlan& plan, int y0, int y1,
                   std::vector<FogDensity>& density) {
  const FroxelGrid& g = view.grid;
  const int nx = g.nx();
  const int samples = plan.samples;
  const float* centers = plan.centers.data();
  std::vector<const VolumeFootprint*> covering;
  std::vector<FogDensity> sample_fog;  // height fog at the volume slices' stratified points
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < nx; ++x) {
      const size_t c = size_t(y) * nx + x;
      const glm::vec3 dir = view.directions[c];
      const int n = view.lit_slices[c];
      FogDensity* column = density.data() + g.index(x, y, 0);
      medium.height_fog_column(dir, centers, n, column);
      // Volumes in file order: the blend result does not depend on scheduling.
      covering.clear();
      int k_begin = n, k_end = 0;
      for (const VolumeFootprint& f : plan.footprints) {
        if (x < f.x0 || x > f.x1 || y < f.y0 || y > f.y1) continue;
        covering.push_back(&f);
        k_begin = std::min(k_begin, f.k0);
        k_end = std::max(k_end, std::min(f.k1 + 1, n));
      }
      if (samples > 1 && k_begin < k_end) {
        sample_fog.resize(size_t(k_end - k_begin) * samples);
        medium.height_fog_column(dir, plan.sample_t.data() + size_t(k_begin) * samples, (k_end - k_begin) * samples,
                                 sample_fog.data());
      }
      for (int k = k_begin; k < k_end; ++k) {
        FogDensity sum;
        bool inside = false;  // whether a point of the froxel lies in a volume
        for (int s = 0; s < samples; ++s) {
          const glm::vec3 p = dir * (samples == 1 ? centers[k] : plan.sample_t[size_t(k) * samples + size_t(s)]);
          FogDensity d = samples == 1 ? column[k] : sample_fog[size_t(k - k_begin) * samples + size_t(s)];
          for (const VolumeFootprint* f : covering)
            if (k >= f->k0 && k <= f->k1) inside |= medium.apply_volume(medium.volumes()[size_t(f->volume)], p, d);
          sum.scattering += d.scattering;
          sum.extinction += d.extinction;
        }
        // A froxel no volume reaches keeps its centre's height fog, as it
        // would outside every footprint.
        if (!inside) continue;
        const float inv = 1.0f / float(samples);
        column[k] = FogDensity{sum.scattering * inv, sum.extinction * inv};
      }
    }
}

VoxelizeStats voxelize_density(const FroxelView& view, const FogMedium& medium, int samples, JobSystem& jobs,
                               std::vector<FogDensity>& density) {
  density.resize(view.grid.count());
  const DensityPlan plan = plan_density(view, medium, samples);
  jobs.parallel_for("fog.density", size_t(view.grid.ny()), 1, [&](size_t begin, size_t end) {
    voxelize_rows(view, medium, plan, int(begin), int(end), density);
  });
  return plan.stats;
}

}  // namespace cr

#include "engine/render/edge_fragments.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/render/view_distance.h"

namespace cr {

namespace {

// Whether reversed-Z depth z at screen position (px, py) lies on the plane of
// the triangle behind `t`: there z = znear / w and the planes' sum is 1 / w.
bool on_plane(const TriangleInterp& t, float px, float py, float z, float znear) {
  const float dx = px - t.ref_x, dy = py - t.ref_y;
  float inv_w = 0.0f;
  for (int i = 0; i < 3; ++i) inv_w += t.u0[i] + (t.ux[i] * dx + t.uy[i] * dy);
  return std::abs(znear * inv_w - z) <= kSurfaceDepthTolerance * z;
}

// The interpolation planes of triangle ids met along neighbouring edge
// pixels, looked up once (direct-mapped by id).
class InterpCache {
 public:
  explicit InterpCache(const TiledRasterizer& raster) : raster_(raster) { ids_.fill(kNoTriangle); }
  const TriangleInterp& operator()(uint32_t id) {
    const size_t slot = (id ^ (id >> 7)) % kSlots;
    if (ids_[slot] != id) {
      ids_[slot] = id;
      interps_[slot] = &raster_.interp(id);
    }
    return *interps_[slot];
  }

 private:
  static constexpr size_t kSlots = 64;
  const TiledRasterizer& raster_;
  std::array<uint32_t, kSlots> ids_;
  std::array<const TriangleInterp*, kSlots> interps_{};
};

}  // namespace

void classify_samples(const TiledRasterizer& raster, const Camera& cam, JobSystem& jobs, std::vector<uint32_t>& ids,
                      std::vector<float>& depth, std::vector<EdgeFragment>& fragments, FragmentRows& rows) {
  const VisibilityBuffer& vis = raster.visibility();
  const int w = vis.width;
  const bool merge = !cam.orthographic;
  const PixelRays rays(cam, w, vis.height);
  const SamplePattern& pattern = vis.pattern;
  const int n = pattern.count;
  ids.resize(vis.triangle.size());
  depth.resize(vis.depth.size());
  rows.resize(vis.mixed.size());
  const float inv_n = 1.0f / float(n);
  jobs.parallel_for("samples", vis.mixed.size(), 1, [&](size_t t0, size_t t1) {
    InterpCache interp(raster);
    for (size_t tile = t0; tile < t1; ++tile) {
      const PixelRect r = vis.grid.tile_rect(int(tile));
      for (int y = r.y0; y <= r.y1; ++y) {
        const size_t row = size_t(y) * size_t(w) + size_t(r.x0), len = size_t(r.x1 - r.x0 + 1);
        std::copy_n(vis.triangle.begin() + ptrdiff_t(row), len, ids.begin() + ptrdiff_t(row));
        std::copy_n(vis.depth.begin() + ptrdiff_t(row), len, depth.begin() + ptrdiff_t(row));
      }
      const MixedSamples& mixed = vis.mixed[tile];
      std::vector<EdgeFragment>& out = rows[tile];
      out.clear();
      for (size_t m = 0; m < mixed.pixels.size(); ++m) {
        const uint32_t i = mixed.pixels[m];
        const int x = int(i % uint32_t(w)), y = int(i / uint32_t(w));
        const uint32_t* sample_id = &mixed.triangle[m * size_t(n)];
        const float* sample_z = &mixed.depth[m * size_t(n)];
        // Distinct surfaces in first-sample order: count, offset and depth sums.
        uint32_t id[kMaxSamples], draw[kMaxSamples];
        int count[kMaxSamples];
        float sum_dx[kMaxSamples], sum_dy[kMaxSamples], sum_z[kMaxSamples];
        int distinct = 0;
        for (int s = 0; s < n; ++s) {
          const uint32_t t = sample_id[s];
          const float z = sample_z[s];
          int k = 0;
          while (k < distinct && id[k] != t) ++k;
          if (k == distinct && merge && t != kNoTriangle) {
            // Another triangle of a surface already seen, continuing its plane?
            const uint32_t d = interp(t).draw_index;
            const float px = float(x) + 0.5f + pattern.dx(s), py = float(y) + 0.5f + pattern.dy(s);
            k = 0;
            while (k < distinct &&
                   !(id[k] != kNoTriangle && draw[k] == d && on_plane(interp(id[k]), px, py, z, cam.znear)))
              ++k;
          }
          if (k == distinct) {
            id[k] = t;
            draw[k] = t == kNoTriangle ? 0 : interp(t).draw_index;
            count[k] = 0;
            sum_dx[k] = sum_dy[k] = sum_z[k] = 0.0f;
            ++distinct;
          }
          ++count[k];
          sum_dx[k] += pattern.dx(s);
          sum_dy[k] += pattern.dy(s);
          sum_z[k] += z;
        }
        if (distinct == 1) {  // one surface: shaded as a pixel inside one triangle
          ids[i] = id[0];
          depth[i] = sum_z[0] * inv_n;
          continue;
        }
        for (int k = 0; k < distinct; ++k) {
          EdgeFragment f;
          f.pixel = i;
          f.triangle = id[k];
          const float c = float(count[k]);
          f.x = float(x) + 0.5f + sum_dx[k] / c;
          f.y = float(y) + 0.5f + sum_dy[k] / c;
          f.weight = c * inv_n;
          f.depth = id[k] == kNoTriangle ? 0.0f : sum_z[k] / c;
          f.distance = view_distance(cam, rays, f.x, f.y, f.depth);
          out.push_back(f);
        }
      }
    }
  });
  fragments.clear();
  for (const std::vector<EdgeFragment>& row : rows) fragments.insert(fragments.end(), row.begin(), row.end());
  // Edge pixels: the farthest fragment's depth, and the id that finds their fragments.
  for (size_t f = 0; f < fragments.size(); ++f) {
    const uint32_t i = fragments[f].pixel;
    if (f == 0 || fragments[f - 1].pixel != i) {
      ids[i] = edge_pixel_id(uint32_t(f));
      depth[i] = fragments[f].depth;
    }
    depth[i] = std::min(depth[i], fragments[f].depth);
  }
}

std::vector<size_t> fragment_chunks(const std::vector<EdgeFragment>& fragments, size_t grain) {
  std::vector<size_t> starts;
  for (size_t b = 0; b < fragments.size();) {
    starts.push_back(b);
    b = std::min(b + grain, fragments.size());
    while (b < fragments.size() && fragments[b].pixel == fragments[b - 1].pixel) ++b;
  }
  starts.push_back(fragments.size());
  return starts;
}

void resolve_fragments(const std::vector<EdgeFragment>& fragments, std::vector<glm::vec3>& color, JobSystem& jobs) {
  // Chunks start at a pixel's first fragment, so each pixel has one writer.
  const std::vector<size_t> starts = fragment_chunks(fragments, 4096);
  jobs.parallel_for("resolve fragments", starts.size() - 1, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c)
      for (size_t f = starts[c]; f < starts[c + 1];) {
        const uint32_t pixel = fragments[f].pixel;
        glm::vec3 sum = fragments[f].color * fragments[f].weight;
        for (++f; f < starts[c + 1] && fragments[f].pixel == pixel; ++f) sum += fragments[f].color * fragments[f].weight;
        color[pixel] = sum;
      }
  });
}

}  // namespace cr

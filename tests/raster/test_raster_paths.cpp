// The rasterizer's fast paths against their plain counterparts, bit for bit:
// the eight-lane vertex projection against project_vertex, the batched setup
// against setup_triangle, and every tile path (tiny triangles from their
// setup-time masks, small ones by spans, large ones by 8x8 blocks with
// trivial accept and reject, spans moved left at tile edges) against a
// per-pixel evaluation of the same edge functions and depth planes.
#include <doctest/doctest.h>

#include <xmmintrin.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "engine/raster/triangle_setup.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

using test::Random;

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Triangles of every size class around a perspective camera: sub-pixel and
// few-pixel ones (tiny), up to 64 pixels (small), large and long slivers
// (blocks), some crossing the near plane or far outside the guard band.
Primitive mixed_triangles(uint64_t seed, int count) {
  Random rng(seed);
  Primitive p;
  for (int t = 0; t < count; ++t) {
    const float kind = rng.next();
    const float size = kind < 0.5f ? rng.range(0.002f, 0.05f) : kind < 0.8f ? rng.range(0.05f, 0.6f) : rng.range(0.6f, 6.0f);
    const glm::vec3 c(rng.range(-6, 6), rng.range(-4, 4), rng.range(-25, 1.5f));
    glm::vec3 d1(rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1)), d2(rng.range(-1, 1), rng.range(-1, 1), rng.range(-1, 1));
    if (rng.next() < 0.1f) d2 = d1 * 0.999f + glm::vec3(0.0f, 0.01f, 0.0f);  // slivers
    for (const glm::vec3& v : {c, c + size * d1, c + size * d2}) {
      p.positions.push_back(v);
      p.indices.push_back(uint32_t(p.positions.size() - 1));
    }
  }
  // A few far beyond the guard band and behind the eye.
  for (int t = 0; t < 20; ++t) {
    const glm::vec3 c(rng.range(-4000, 4000), rng.range(-4000, 4000), rng.range(-50, 5));
    for (int k = 0; k < 3; ++k) {
      p.positions.push_back(c + glm::vec3(rng.range(-3000, 3000), rng.range(-3000, 3000), rng.range(-10, 10)));
      p.indices.push_back(uint32_t(p.positions.size() - 1));
    }
  }
  return p;
}

struct Scene {
  int width, height;
  Camera cam;
  Primitive a, b;
  Scene(int w, int h, uint64_t seed)
      : width(w), height(h), cam(Camera::look_at({0.0, 0.5, 3.0}, {0.0, 0.0, -5.0}, 1.0f, float(w) / h, 0.1f)),
        a(mixed_triangles(seed, 5000)), b(mixed_triangles(seed + 1, 3000)) {}
  std::vector<RasterDraw> draws(bool alpha) const {
    std::vector<RasterDraw> d{test::draw_of(a, test::world_to_clip(cam), 0, false),
                              test::draw_of(b, test::world_to_clip(cam), 1, true)};
    d[1].mirrored = true;
    d[1].alpha_mask = alpha;
    return d;
  }
};

SetupParams params_for(int width, int height, CullMode cull, int32_t margin) {
  SetupParams p;
  p.width = width;
  p.height = height;
  p.band = GuardBand::for_image(width, height, kGuardBandPixels);
  p.cull = cull;
  p.sample_margin = margin;
  p.sx = 2.0 / width;
  p.sy = -2.0 / height;
  return p;
}

// The geometry of one render call as TiledRasterizer::build makes it, with
// setup_triangle one triangle at a time (the plain path).
std::vector<SetupBatch> plain_setup(std::span<const RasterDraw> draws, const SetupParams& params) {
  std::vector<ProjectedVertex> vertices;
  std::vector<size_t> base;
  for (const RasterDraw& d : draws) {
    base.push_back(vertices.size());
    for (const glm::vec3& p : d.primitive->positions)
      vertices.push_back(project_vertex(d.model_to_clip * glm::vec4(p, 1.0f), params));
  }
  std::vector<SetupBatch> chunks;
  size_t tri = 0;
  for (size_t d = 0; d < draws.size(); ++d)
    for (uint32_t t = 0; t < draws[d].primitive->triangle_count(); ++t, ++tri) {
      if (tri % TiledRasterizer::kSetupChunk == 0) chunks.emplace_back().clear(uint32_t(tri));  // set 0: id = chunk << 10 | index
      const uint32_t* idx = &draws[d].primitive->indices[3 * size_t(t)];
      setup_triangle(vertices[base[d] + idx[0]], vertices[base[d] + idx[1]], vertices[base[d] + idx[2]], draws[d], t,
                     params, chunks.back());
    }
  return chunks;
}

// The depth a tile job computes for pixel (x, y) (SSE max/min: the bound where unordered).
float plane_depth(const ScreenTriangle& t, int x, int y) {
  const float z = t.z0 + (t.zx * float(x - t.ref_x) + t.zy * float(y - t.ref_y));
  return _mm_cvtss_f32(_mm_min_ss(_mm_max_ss(_mm_set_ss(z), _mm_set_ss(t.z_min)), _mm_set_ss(t.z_max)));
}

bool covers(const ScreenTriangle& t, int x, int y) {
  for (int e = 0; e < 3; ++e)
    if (t.c(e) + int64_t(t.a[e]) * x + int64_t(t.b[e]) * y < 0) return false;
  return true;
}

struct Reference {
  std::vector<float> depth;
  std::vector<uint32_t> ids;
};

// Visibility or depth by testing every pixel of every piece's bounds in submission order.
Reference reference_raster(const std::vector<SetupBatch>& chunks, int width, int height, const CoverageFn& coverage) {
  Reference r{std::vector<float>(size_t(width) * height, 0.0f), std::vector<uint32_t>(size_t(width) * height, kNoTriangle)};
  for (const SetupBatch& chunk : chunks)
    for (size_t k = 0; k < chunk.triangles.size(); ++k) {
      const ScreenTriangle& t = chunk.triangles[k];
      const PixelRect& b = chunk.bounds[k];
      for (int y = b.y0; y <= b.y1; ++y)
        for (int x = b.x0; x <= b.x1; ++x) {
          if (!covers(t, x, y)) continue;
          const float z = plane_depth(t, x, y);
          const size_t i = size_t(y) * width + x;
          if (!(z > r.depth[i])) continue;
          if (t.alpha_mask && !coverage(t.id, interpolate(chunk.interps[t.interp], float(x) + 0.5f, float(y) + 0.5f)))
            continue;
          r.depth[i] = z;
          r.ids[i] = t.id;
        }
    }
  return r;
}

size_t depth_mismatches(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += !same_bits(a[i], b[i]);
  return n;
}

size_t id_mismatches(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

TEST_CASE("project_vertices gives project_vertex's bits, lane by lane") {
  Random rng(3);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<glm::vec3> positions;
  for (int i = 0; i < 2003; ++i) {  // not a multiple of 8: the tail takes project_vertex itself
    const float scale = i % 7 == 0 ? 1e5f : i % 5 == 0 ? 1e-3f : 10.0f;
    positions.emplace_back(rng.range(-1, 1) * scale, rng.range(-1, 1) * scale, rng.range(-1, 1) * scale);
  }
  positions[10] = {nan, 0, 0};
  positions[11] = {0, inf, 0};
  positions[12] = {-inf, 0, 1};
  positions[13] = {3e38f, 3e38f, 3e38f};  // overflows to infinity in the transform
  positions[14] = {0, 0, 0};
  const Camera persp = Camera::look_at({1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, 1.0f, 1.5f, 0.05f);
  for (const glm::mat4& m : {test::world_to_clip(persp), test::pixel_to_clip(300, 200),
                             glm::mat4(glm::vec4(0.3f, -1.2f, 0.7f, 0.1f), glm::vec4(2.0f, 0.5f, -0.3f, -0.4f),
                                       glm::vec4(-0.6f, 0.9f, 1.1f, 0.8f), glm::vec4(0.2f, -0.1f, 0.4f, 1.0f))}) {
    for (auto [w, h] : {std::pair{300, 200}, std::pair{1280, 720}, std::pair{7, 5}}) {
      const SetupParams params = params_for(w, h, CullMode::Back, 0);
      std::vector<ProjectedVertex> fast(positions.size());
      project_vertices(positions.data(), positions.size(), m, params, fast.data());
      size_t wrong = 0;
      for (size_t i = 0; i < positions.size(); ++i) {
        const ProjectedVertex plain = project_vertex(m * glm::vec4(positions[i], 1.0f), params);
        const ProjectedVertex& f = fast[i];
        wrong += std::memcmp(&plain.clip, &f.clip, sizeof plain.clip) != 0 || plain.x != f.x || plain.y != f.y ||
                 !same_bits(plain.z, f.z) || plain.outcode != f.outcode;
      }
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("batched setup gives setup_triangle's results: counts, pieces, masks, planes") {
  constexpr int W = 320, H = 200;
  const Scene scene(W, H, 5);
  for (bool alpha : {false, true})
    for (CullMode cull : {CullMode::Back, CullMode::None})
      for (int32_t margin : {0, 96}) {
        CAPTURE(alpha);
        CAPTURE(int(cull));
        CAPTURE(margin);
        const std::vector<RasterDraw> draws = scene.draws(alpha);
        const SetupParams params = params_for(W, H, cull, margin);
        const std::vector<SetupBatch> plain = plain_setup(draws, params);
        // The batched path over the same chunks.
        std::vector<ProjectedVertex> vertices[2];
        for (int d = 0; d < 2; ++d) {
          vertices[d].resize(draws[d].primitive->positions.size());
          project_vertices(draws[d].primitive->positions.data(), vertices[d].size(), draws[d].model_to_clip, params,
                           vertices[d].data());
        }
        size_t tri = 0, c = 0;
        std::vector<SetupBatch> fast(plain.size());
        while (tri < scene.a.triangle_count() + scene.b.triangle_count()) {
          SetupBatch& out = fast[c];
          out.clear(uint32_t(tri));
          const size_t end = tri + TiledRasterizer::kSetupChunk;
          for (int d = 0; d < 2 && tri < end; ++d) {
            const size_t first = d == 0 ? 0 : scene.a.triangle_count();
            const size_t last = first + draws[d].primitive->triangle_count();
            if (tri >= last) continue;
            const size_t stop = std::min(end, last);
            setup_triangles(vertices[d].data(), vertices[d].size(), draws[d], uint32_t(tri - first), uint32_t(stop - tri),
                            params, out);
            tri = stop;
          }
          ++c;
        }
        REQUIRE(c == plain.size());
        size_t pieces = 0, tiny = 0, large = 0, clipped = 0, wrong = 0;
        for (size_t k = 0; k < plain.size(); ++k) {
          const SetupBatch &p = plain[k], &f = fast[k];
          clipped += p.counters.clipped;
          CHECK(p.counters.in == f.counters.in);
          CHECK(p.counters.culled == f.counters.culled);
          CHECK(p.counters.clipped == f.counters.clipped);
          CHECK(p.counters.visible == f.counters.visible);
          CHECK(p.counters.screen == f.counters.screen);
          CHECK(p.interps.size() == f.interps.size());
          REQUIRE(p.triangles.size() == f.triangles.size());
          for (size_t i = 0; i < p.triangles.size(); ++i) {
            const ScreenTriangle &s = p.triangles[i], &t = f.triangles[i];
            bool same = s.mask == t.mask && s.id == t.id && s.interp == t.interp && s.alpha_mask == t.alpha_mask &&
                        s.small == t.small && s.tiny == t.tiny && s.ref_x == t.ref_x && s.ref_y == t.ref_y &&
                        same_bits(s.z0, t.z0) && same_bits(s.zx, t.zx) && same_bits(s.zy, t.zy) &&
                        same_bits(s.z_min, t.z_min) && same_bits(s.z_max, t.z_max);
            for (int e = 0; e < 3; ++e) same &= s.a[e] == t.a[e] && s.b[e] == t.b[e] && s.c_num[e] == t.c_num[e];
            const PixelRect &pb = p.bounds[i], &fb = f.bounds[i];
            same &= pb.x0 == fb.x0 && pb.y0 == fb.y0 && pb.x1 == fb.x1 && pb.y1 == fb.y1;
            const TriangleInterp &pi = p.interps[s.interp], &fi = f.interps[t.interp];
            same &= std::memcmp(&pi, &fi, offsetof(TriangleInterp, front_facing)) == 0 && pi.front_facing == fi.front_facing;
            wrong += !same;
            ++pieces;
            tiny += s.tiny;
            large += !s.small;
          }
        }
        CHECK(wrong == 0);
        // Every path is exercised.
        CHECK(pieces > 1500);
        CHECK(large > 200);
        CHECK(clipped > 20);
        if (margin == 0) CHECK(tiny > 500);
      }
}

TEST_CASE("tile paths match a per-pixel evaluation of the edges and depth planes, any tile size and thread count") {
  const CoverageFn coverage = [](uint32_t id, const Barycentrics& b) { return (id & 3) != 0 || b.b.x < 0.4f; };
  for (auto [w, h] : {std::pair{320, 200}, std::pair{203, 117}}) {  // 203: last tile columns narrower than a span
    const Scene scene(w, h, 17);
    const std::vector<RasterDraw> draws = scene.draws(true);
    const std::vector<SetupBatch> chunks =
        plain_setup(draws, params_for(w, h, CullMode::Back, 0));
    const Reference ref = reference_raster(chunks, w, h, coverage);
    size_t drawn = 0;
    for (uint32_t id : ref.ids) drawn += id != kNoTriangle;
    CHECK(drawn > size_t(w * h / 4));
    for (unsigned threads : {1u, 3u}) {
      JobSystem jobs(threads);
      for (int tile : {8, 16, 64, 256}) {
        CAPTURE(w);
        CAPTURE(threads);
        CAPTURE(tile);
        TiledRasterizer r;
        r.render_visibility(jobs, w, h, tile, draws, coverage);
        CHECK(depth_mismatches(r.visibility().depth, ref.depth) == 0);
        CHECK(id_mismatches(r.visibility().triangle, ref.ids) == 0);
      }
    }
  }
}

TEST_CASE("depth-only and blended tiles match the per-pixel evaluation") {
  constexpr int W = 211, H = 133;
  const Scene scene(W, H, 23);
  const std::vector<RasterDraw> draws = scene.draws(false);
  JobSystem jobs(2);
  // Depth only (a W x W image): both faces, nothing culled.
  const std::vector<SetupBatch> both = plain_setup(draws, params_for(W, W, CullMode::None, 0));
  const Reference ref = reference_raster(both, W, W, {});
  std::vector<float> depth;
  for (int tile : {8, 32, 128}) {
    TiledRasterizer r;
    r.render_depth(jobs, W, tile, draws, depth);
    CHECK(depth_mismatches(depth, ref.depth) == 0);
  }
  // Blended over an opaque pass of draw 0: fragments of draw 1 in front of it, in order.
  const std::vector<SetupBatch> opaque = plain_setup({draws.data(), 1}, params_for(W, H, CullMode::Back, 0));
  const Reference front = reference_raster(opaque, W, H, {});
  std::vector<std::vector<uint32_t>> expected(size_t(W) * H);
  for (const SetupBatch& chunk : plain_setup({draws.data() + 1, 1}, params_for(W, H, CullMode::Back, 0)))
    for (size_t k = 0; k < chunk.triangles.size(); ++k) {
      const ScreenTriangle& t = chunk.triangles[k];
      const PixelRect& b = chunk.bounds[k];
      for (int y = b.y0; y <= b.y1; ++y)
        for (int x = b.x0; x <= b.x1; ++x)
          if (covers(t, x, y) && plane_depth(t, x, y) > front.depth[size_t(y) * W + x])
            expected[size_t(y) * W + x].push_back(t.id & ((1u << 30) - 1));
    }
  for (int tile : {8, 64}) {
    TiledRasterizer r;
    r.render_visibility(jobs, W, H, tile, {draws.data(), 1});
    CHECK(depth_mismatches(r.visibility().depth, front.depth) == 0);
    std::vector<std::vector<uint32_t>> seen(size_t(W) * H);
    r.render_blended(jobs, {draws.data() + 1, 1}, [&](int x, int y, uint32_t id, const Barycentrics&, float) {
      seen[size_t(y) * W + x].push_back(id & ((1u << 30) - 1));
    });
    CHECK(seen == expected);
  }
}

}  // namespace
}  // namespace cr

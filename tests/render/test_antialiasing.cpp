// Multisampled frames: edge pixels become fragments with the right weights,
// positions and distances; a mesh's inner edges are no edges; plugin
// composites see each fragment's own distance; the resolve is the weighted
// sum; frames are bit-identical for any thread count.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "engine/core/profile.h"
#include "engine/render/edge_fragments.h"
#include "engine/render/renderer.h"
#include "engine/render/view_distance.h"
#include "engine/scene/gltf_loader.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int W = 48, H = 32;

// A camera at the origin looking down -Z at two quads: a near one (draw 0,
// two triangles on one plane) over the left part of the view, its right edge
// at screen x = edge_x, and a far one (draw 1) behind everything.
struct TwoQuads {
  Camera cam = Camera::look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 1.0f, float(W) / H, 0.1f);
  Primitive near_quad, far_quad;
  float edge_x;

  explicit TwoQuads(float edge_px) : edge_x(edge_px) {
    // View-space x at depth 5 of screen x: (2 px / W - 1) * tan(fov/2) * aspect * 5.
    const float t = std::tan(0.5f * cam.vfov_rad) * cam.aspect;
    const float xr = (2.0f * edge_px / W - 1.0f) * t * 5.0f;
    near_quad = test::make_primitive({{-50, -50, -5}, {xr, -50, -5}, {xr, 50, -5}, {-50, 50, -5}}, {0, 1, 2, 0, 2, 3});
    far_quad = test::make_primitive({{-90, -90, -10}, {90, -90, -10}, {90, 90, -10}, {-90, 90, -10}}, {0, 1, 2, 0, 2, 3});
  }
  std::vector<RasterDraw> draws() const {
    return {test::draw_of(near_quad, test::world_to_clip(cam), 0), test::draw_of(far_quad, test::world_to_clip(cam), 1)};
  }
};

TEST_CASE("edge fragments: a vertical edge's pixels split by their samples, centroids and distances their own") {
  JobSystem jobs(2);
  for (int samples : {2, 4, 8}) {
    const TwoQuads scene(20.3f);
    const std::vector<RasterDraw> draws = scene.draws();
    TiledRasterizer r;
    r.render_visibility(jobs, W, H, 16, draws, {}, samples);
    std::vector<uint32_t> ids;
    std::vector<float> depth;
    std::vector<EdgeFragment> fragments;
    FragmentRows rows;
    classify_samples(r, scene.cam, jobs, ids, depth, fragments, rows);
    const SamplePattern p = sample_pattern(samples);
    // The near quad's diagonal is an inner edge: only column 20 has fragments.
    std::map<uint32_t, std::vector<const EdgeFragment*>> by_pixel;
    for (const EdgeFragment& f : fragments) by_pixel[f.pixel].push_back(&f);
    CAPTURE(samples);
    CHECK(by_pixel.size() == size_t(H));
    int expected_near = 0;
    float near_dx = 0.0f;
    for (int s = 0; s < samples; ++s)
      if (20.5f + p.dx(s) < 20.3f) {
        ++expected_near;
        near_dx += p.dx(s);
      }
    for (const auto& [pixel, list] : by_pixel) {
      CHECK(int(pixel % W) == 20);
      CHECK(is_edge_pixel(ids[pixel]));
      CHECK(first_fragment(ids[pixel]) == size_t(list[0] - fragments.data()));
      REQUIRE(list.size() == 2);
      double weights = 0.0;
      for (const EdgeFragment* f : list) weights += f->weight;
      CHECK(weights == doctest::Approx(1.0).epsilon(1e-6));
      const EdgeFragment& nearer = r.ref(list[0]->triangle).draw_index == 0 ? *list[0] : *list[1];
      const EdgeFragment& farther = &nearer == list[0] ? *list[1] : *list[0];
      CHECK(nearer.weight == float(expected_near) / float(samples));
      CHECK(nearer.x == doctest::Approx(20.5f + near_dx / float(expected_near)));
      // Each fragment's distance is its own surface's along its own ray.
      const float y = nearer.y;
      CHECK(nearer.distance == doctest::Approx(view_distance(scene.cam, W, H, nearer.x, y, nearer.depth)));
      CHECK(nearer.distance < 6.0f);
      CHECK(farther.distance > 9.9f);
      CHECK(depth[pixel] == farther.depth);  // the pixel keeps the farthest fragment's depth
    }
    // Away from the edge, pixels hold one triangle each.
    for (int y = 0; y < H; ++y) {
      CHECK(!is_edge_pixel(ids[size_t(y) * W + 5]));
      CHECK(!is_edge_pixel(ids[size_t(y) * W + 40]));
    }
  }
}

TEST_CASE("edge fragments: a fold of one mesh in depth stays an edge; the resolve is the weighted sum") {
  JobSystem jobs(1);
  const Camera cam = Camera::look_at({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 1.0f, float(W) / H, 0.1f);
  // One draw: a near strip in front of a far wall, meeting nowhere.
  Primitive mesh = test::make_primitive(
      {{-0.4f, -9, -4}, {0.4f, -9, -4}, {0.4f, 9, -4}, {-9, -9, -8}, {9, -9, -8}, {9, 9, -8}, {-9, 9, -8}},
      {0, 1, 2, 3, 4, 5, 3, 5, 6});
  const RasterDraw d = test::draw_of(mesh, test::world_to_clip(cam), 0);
  TiledRasterizer r;
  r.render_visibility(jobs, W, H, 16, std::span(&d, 1), {}, 4);
  std::vector<uint32_t> ids;
  std::vector<float> depth;
  std::vector<EdgeFragment> fragments;
  FragmentRows rows;
  classify_samples(r, cam, jobs, ids, depth, fragments, rows);
  CHECK(fragments.size() > 20);
  // Resolve: the fragments' colours weighted, in order.
  std::vector<glm::vec3> color(size_t(W) * H, glm::vec3(-1.0f));
  for (size_t k = 0; k < fragments.size(); ++k) fragments[k].color = glm::vec3(float(k % 5), 1.0f, fragments[k].distance);
  resolve_fragments(fragments, color, jobs);
  for (size_t k = 0; k < fragments.size();) {
    const uint32_t pixel = fragments[k].pixel;
    glm::vec3 sum = fragments[k].color * fragments[k].weight;
    for (++k; k < fragments.size() && fragments[k].pixel == pixel; ++k) sum += fragments[k].color * fragments[k].weight;
    CHECK(color[pixel] == sum);
  }
}

// A plugin whose composite writes a function of the distance, for pixels and fragments alike.
class DistancePlugin : public Plugin {
 public:
  std::string name() const override { return "distance"; }
  bool configure(const Scene&, const SceneDescription&, const Profile&) override { return true; }
  void add_passes(FrameGraph&, const FrameContext&, EngineResources&) override {}
  bool has_composite() const override { return true; }
  static glm::vec3 of(float distance) {
    return std::isfinite(distance) ? glm::vec3(1.0f / (1.0f + distance), 0.5f, 0.0f) : glm::vec3(0.0f, 0.0f, 9.0f);
  }
  void composite(FrameBuffers& buffers, int x0, int y0, int x1, int y1) override {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) buffers.color[buffers.index(x, y)] = of(buffers.distance[buffers.index(x, y)]);
  }
  void composite_fragments(const FrameBuffers&, std::span<EdgeFragment> fragments) override {
    for (EdgeFragment& f : fragments) f.color = of(f.distance);
  }
};

TEST_CASE("multisampled frames: a plugin composites each fragment at its own distance; the resolve weighs them") {
  const SceneDescription description =
      load_scene_description(std::string(CR_ASSIMP_GLTF_DIR) + "/BoxTextured-glTF/BoxTextured.gltf", {});
  const Scene scene = load_gltf(description.gltf_path);
  Profile profile;
  profile.width = 64;
  profile.height = 48;
  profile.msaa_samples = 4;
  JobSystem jobs(2);
  std::vector<std::unique_ptr<Plugin>> plugins;
  plugins.push_back(std::make_unique<DistancePlugin>());
  Renderer renderer(scene, description, profile, std::move(plugins), jobs);
  renderer.render_frame(0);
  const FrameBuffers& b = renderer.buffers();
  REQUIRE(!b.fragments.empty());
  int mixed_sky = 0;
  for (size_t k = 0; k < b.fragments.size();) {
    const uint32_t pixel = b.fragments[k].pixel;
    glm::vec3 sum(0.0f);
    bool sky = false, surface = false;
    for (bool first = true; k < b.fragments.size() && b.fragments[k].pixel == pixel; ++k, first = false) {
      const EdgeFragment& f = b.fragments[k];
      CHECK(f.color == DistancePlugin::of(f.distance));
      sum = first ? f.color * f.weight : sum + f.color * f.weight;
      sky |= f.triangle == kNoTriangle;
      surface |= f.triangle != kNoTriangle;
    }
    CHECK(b.color[pixel] == sum);
    mixed_sky += sky && surface;
  }
  CHECK(mixed_sky > 10);  // the box's silhouette against nothing
}

struct Village {
  SceneDescription description;
  Profile profile;
  Scene scene;
};

std::vector<uint8_t> render_display(const Village& v, unsigned threads) {
  JobSystem jobs(threads);
  Renderer r(v.scene, v.description, v.profile, {}, jobs);
  r.render_frame(0);
  CHECK(!r.buffers().fragments.empty());
  return r.buffers().display;
}

TEST_CASE("determinism: a multisampled frame of the default scene is bit-identical for 1..8 threads") {
  const std::string path = std::string(CR_BINARY_DIR) + "/scenes/engine_only.json";
  REQUIRE(std::filesystem::exists(path));
  Village v;
  v.description = load_scene_description(path, {});
  v.profile = load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  v.profile.width = 192;
  v.profile.height = 108;
  v.scene = load_gltf(v.description.gltf_path);
  for (int samples : {4, 8}) {
    v.profile.msaa_samples = samples;
    const std::vector<uint8_t> one = render_display(v, 1);
    for (unsigned t = 2; t <= 8; ++t) {
      CAPTURE(samples);
      CAPTURE(t);
      CHECK(render_display(v, t) == one);
    }
  }
}

}  // namespace
}  // namespace cr

// Khronos NormalTangentTest: each test cell pairs real bumps (left) with a
// flat quad whose normal map was baked from them (right), and the file has no
// tangents, so the renderer generates them. Lit by a sun from above and then
// from the side, each normal-mapped half must be lit from the same side as
// its geometry twin; with the bitangent flipped (the "flipped Y" failure the
// model documents) light from above lands on the bottom of the bumps.
#include <doctest/doctest.h>

#include <fstream>
#include <vector>

#include "engine/core/luminance.h"
#include "engine/render/renderer.h"
#include "engine/scene/gltf_loader.h"
#include "tests/khronos_assets.h"

namespace {

constexpr int kSize = 400;

// Linear luminance of a frame of the model seen face-on under one sun.
std::vector<float> render_lit(const cr::Scene& scene, const std::string& gltf, float azimuth, float elevation) {
  const std::string file = std::string(CR_BINARY_DIR) + "/normal_tangent_test.json";
  std::ofstream(file) << R"({"gltf": ")" << gltf << R"(",
    "camera": {"position": [0, 0, 3.2], "target": [0, 0, 0], "vfov_deg": 45},
    "sun": {"azimuth_deg": )" << azimuth << R"(, "elevation_deg": )" << elevation << R"(, "illuminance": 100000},
    "ambient": [0, 0, 0]})";
  const cr::SceneDescription d = cr::load_scene_description(file, {});
  cr::Profile profile = cr::load_profile(std::string(CR_SOURCE_DIR) + "/profiles/desktop.json", {"atmosphere", "fog"});
  profile.width = profile.height = kSize;
  cr::JobSystem jobs(2);
  cr::Renderer r(scene, d, profile, {}, jobs);
  r.render_frame(0);
  std::vector<float> y;
  for (const glm::vec3& c : r.buffers().color) y.push_back(cr::luminance(c));
  return y;
}

// Runs of consecutive true entries, as [first, last] pairs, at least min_len long.
std::vector<std::pair<int, int>> runs(const std::vector<bool>& on, int min_len) {
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < int(on.size());) {
    int j = i;
    while (j < int(on.size()) && on[j]) ++j;
    if (j - i >= min_len) out.push_back({i, j - 1});
    i = j + (j == i);
  }
  return out;
}

struct Rect {
  int x0, x1, y0, y1;
};

// Where the light falls in a cell: the luminance-weighted centroid of its
// pixels, relative to the cell's centre, in units of the cell's size.
glm::vec2 light_centroid(const std::vector<float>& y, const Rect& r) {
  double sx = 0.0, sy = 0.0, s = 0.0;
  for (int py = r.y0; py <= r.y1; ++py)
    for (int px = r.x0; px <= r.x1; ++px) {
      const double v = y[size_t(py) * kSize + px];
      sx += v * px;
      sy += v * py;
      s += v;
    }
  const double cx = 0.5 * (r.x0 + r.x1), cy = 0.5 * (r.y0 + r.y1);
  return {float((sx / s - cx) / (r.x1 - r.x0 + 1)), float((sy / s - cy) / (r.y1 - r.y0 + 1))};
}

}  // namespace

TEST_CASE("NormalTangentTest: generated tangents light each normal-mapped cell like its geometry twin") {
  const auto gltf = cr::test::asset_path("khronos/NormalTangentTest/glTF/NormalTangentTest.gltf");
  if (!gltf) return;
  const cr::Scene scene = cr::load_gltf(*gltf);
  REQUIRE(scene.primitive(scene.draws.at(0)).tangents.size() > 0);

  const std::vector<float> from_above = render_lit(scene, *gltf, 0.0f, 60.0f);
  const std::vector<float> from_right = render_lit(scene, *gltf, 90.0f, 25.0f);
  // The cells: the lit image's bright rows and columns (the dielectric cells'
  // backgrounds are lit by both suns; the metal column is dark without an
  // environment and the "Front" label is one wide cell below the grid).
  auto lit = [&](int px, int py) { return from_above[size_t(py) * kSize + px] > 500.0f; };
  std::vector<bool> row_on(kSize), col_on(kSize);
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px) row_on[py] = row_on[py] || lit(px, py);
  const auto rows = runs(row_on, kSize / 20);
  REQUIRE(rows.size() >= 5);  // five rows of pairs (and the label)
  for (int py = rows[0].first; py <= rows[0].second; ++py)  // columns of the top row only: the label spans a gap
    for (int px = 0; px < kSize; ++px) col_on[px] = col_on[px] || lit(px, py);
  const auto cols = runs(col_on, kSize / 20);
  REQUIRE(cols.size() >= 4);  // two dielectric pairs
  int pairs = 0;
  for (int r = 0; r < 5; ++r)
    for (int pair = 0; pair < 2; ++pair) {
      const Rect geometry{cols[2 * pair].first, cols[2 * pair].second, rows[r].first, rows[r].second};
      const Rect mapped{cols[2 * pair + 1].first, cols[2 * pair + 1].second, rows[r].first, rows[r].second};
      CAPTURE(r);
      CAPTURE(pair);
      // Sun from above: both halves brighter at the top (image y down).
      const glm::vec2 ga = light_centroid(from_above, geometry), ma = light_centroid(from_above, mapped);
      CHECK(ga.y < -0.01f);
      CHECK(ma.y < -0.01f);
      CHECK(std::abs(ga.y - ma.y) < 0.5f * std::abs(ga.y));
      // Sun from the right (+X): both halves brighter on the right.
      const glm::vec2 gr = light_centroid(from_right, geometry), mr = light_centroid(from_right, mapped);
      CHECK(gr.x > 0.01f);
      CHECK(mr.x > 0.01f);
      CHECK(std::abs(gr.x - mr.x) < 0.5f * std::abs(gr.x));
      ++pairs;
    }
  CHECK(pairs == 10);
}

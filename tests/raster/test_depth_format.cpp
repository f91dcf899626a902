// Reduced-precision depth (profile "precision": {"depth": ...}): the formats'
// grids, and what they do to two surfaces 100 m apart at 30 km, where a
// mountain range stands behind another.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>

#include "engine/raster/span8.h"
#include "tests/raster/raster_test_util.h"

namespace cr {
namespace {

constexpr int kFormatW = 96, kFormatH = 64;

// A wall facing a camera at the origin looking down -Z, `distance` metres away, covering the view.
Primitive wall(float distance) {
  const float half = distance;  // wider than the 60 deg view at any distance
  return test::make_primitive({{-half, -half, -distance}, {half, -half, -distance}, {half, half, -distance},
                               {-half, half, -distance}},
                              {0, 1, 2, 0, 2, 3});
}

// Lane 0 of a format's rounding of 8 copies of z.
float quantized(float z, span8::F (*format)(span8::F)) {
  const float in[8] = {z, z, z, z, z, z, z, z};
  const span8::F q = format(span8::load(in));
  float out[8];
  std::memcpy(out, &q, sizeof out);
  return out[0];
}

// Pixels of the nearer wall when the farther one is drawn first.
int nearer_visible(DepthFormat format, float near_distance, float gap) {
  const Camera cam = Camera::look_at(glm::dvec3(0.0), glm::dvec3(0.0, 0.0, -1.0), 1.0471976f, float(kFormatW) / float(kFormatH), 0.1f);
  const glm::mat4 m = test::world_to_clip(cam);
  const Primitive far_wall = wall(near_distance + gap), near_wall = wall(near_distance);
  const RasterDraw draws[] = {test::draw_of(far_wall, m, 0), test::draw_of(near_wall, m, 1)};
  JobSystem jobs(2);
  TiledRasterizer r;
  r.render_visibility(jobs, kFormatW, kFormatH, 16, draws, {}, 1, format);
  int nearer = 0;
  for (uint32_t id : r.visibility().triangle) nearer += id != kNoTriangle && r.ref(id).draw_index == 1 ? 1 : 0;
  return nearer;
}

}  // namespace

TEST_CASE("depth formats: values land on their grid, rounding is monotone and keeps 0 and 1") {
  float prev24 = 0.0f, prevf = 0.0f;
  for (int i = 0; i <= 200000; ++i) {
    const float z = std::exp2(-30.0f * float(i) / 200000.0f * 1.0001f) * (i == 200000 ? 0.0f : 1.0f);
    const float u[1] = {quantized(z, span8::quantize_unorm24)}, f[1] = {quantized(z, span8::quantize_float24)};
    CHECK(u[0] * 16777216.0f == std::round(u[0] * 16777216.0f));
    CHECK((std::bit_cast<uint32_t>(f[0]) & 0x7Fu) == 0u);
    CHECK(std::abs(u[0] - z) <= 0.5f / 16777216.0f);
    CHECK(std::abs(f[0] - z) <= z * std::exp2(-17.0f));
    if (i > 0) {  // z decreases with i
      CHECK(u[0] <= prev24);
      CHECK(f[0] <= prevf);
    }
    prev24 = u[0];
    prevf = f[0];
  }
  CHECK(quantized(1.0f, span8::quantize_unorm24) == 1.0f);
  CHECK(quantized(1.0f, span8::quantize_float24) == 1.0f);
  CHECK(quantized(0.0f, span8::quantize_unorm24) == 0.0f);
  CHECK(quantized(0.0f, span8::quantize_float24) == 0.0f);
}

TEST_CASE("depth formats: two walls 100 m apart at 30 km: float32 and float24 keep their order, unorm24 ties") {
  const int all = kFormatW * kFormatH;
  CHECK(nearer_visible(DepthFormat::Float32, 30000.0f, 100.0f) == all);
  CHECK(nearer_visible(DepthFormat::Float24, 30000.0f, 100.0f) == all);
  // A unorm24 step at 30 km is about 540 m: both walls round to the same depth,
  // and the first drawn (the farther) stays: z-fighting.
  const int unorm = nearer_visible(DepthFormat::Unorm24, 30000.0f, 100.0f);
  MESSAGE("unorm24: the nearer wall shows in " << unorm << " of " << all << " pixels");
  CHECK(unorm < all / 2);
  // Near the camera unorm24 is finer than float24's relative steps: both keep 1 m at 100 m apart.
  CHECK(nearer_visible(DepthFormat::Unorm24, 100.0f, 1.0f) == all);
  CHECK(nearer_visible(DepthFormat::Float24, 100.0f, 1.0f) == all);
}

}  // namespace cr

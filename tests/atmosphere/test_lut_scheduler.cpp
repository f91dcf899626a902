// The amortised update scheduler: which LUTs update when, time slicing behind
// double buffers, the full schedule, the space fallback, determinism.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>

#include "atmosphere/sky_composite.h"
#include "engine/render/composite_strips.h"
#include "atmosphere_test_util.h"

using namespace cr;
using namespace cr::test;

namespace {

std::string work(const AtmospherePlan& p, LutKind k) {
  const LutWork& w = p.work[size_t(k)];
  return w.active ? w.cause : "-";
}

bool same_bits(const LutImage& a, const LutImage& b) {
  return a.texels.size() == b.texels.size() &&
         std::memcmp(a.texels.data(), b.texels.data(), a.texels.size() * sizeof(glm::vec3)) == 0;
}

}  // namespace

TEST_CASE("first frame builds all four LUTs; unchanged inputs never rebuild") {
  JobSystem jobs(2);
  LutScheduler s(small_settings());
  const Camera cam = camera_at(2.0);
  const glm::vec3 sun = sun_from_zenith(40.0);
  const AtmospherePlan p0 = run_frame(s, 0, cam, sun, jobs);
  for (int k = 0; k < kLutKinds; ++k) {
    CHECK(work(p0, LutKind(k)) == "initial");
    CHECK(s.version(LutKind(k)) == 1);
  }
  for (int f = 1; f < 40; ++f) {
    const AtmospherePlan p = run_frame(s, f, cam, sun, jobs);
    for (int k = 0; k < kLutKinds; ++k) CHECK(work(p, LutKind(k)) == "-");
  }
}

TEST_CASE("invalidation follows the dependency graph") {
  JobSystem jobs(2);
  AtmosphereSettings settings = small_settings();
  LutScheduler s(settings);
  const glm::vec3 sun = sun_from_zenith(40.0);
  run_frame(s, 0, camera_at(2.0), sun, jobs);

  SUBCASE("a small sun move waits for the period, then refreshes only sky-view and AP") {
    const glm::vec3 moved = sun_from_zenith(40.1);  // below the 0.5 deg threshold
    for (int f = 1; f < 12; ++f) {
      const AtmospherePlan p = run_frame(s, f, camera_at(2.0), moved, jobs);
      CHECK(work(p, LutKind::Transmittance) == "-");
      CHECK(work(p, LutKind::MultiScattering) == "-");
      CHECK(work(p, LutKind::SkyView) == (f == 4 ? "periodic" : "-"));
      CHECK(work(p, LutKind::AerialPerspective) == (f == 6 ? "periodic" : "-"));
    }
  }
  SUBCASE("a sun move beyond the threshold rebuilds sky-view and AP at once, not transmittance or MS") {
    const AtmospherePlan p = run_frame(s, 1, camera_at(2.0), sun_from_zenith(45.0), jobs);
    CHECK(work(p, LutKind::Transmittance) == "-");
    CHECK(work(p, LutKind::MultiScattering) == "-");
    CHECK(work(p, LutKind::SkyView) == "sun");
    CHECK(work(p, LutKind::AerialPerspective) == "sun");
  }
  SUBCASE("the sun turning in azimuth only does not touch the sky-view LUT") {
    const glm::vec3 turned = glm::vec3(sun.x * std::cos(0.5f), sun.y, sun.x * std::sin(0.5f));
    const AtmospherePlan p = run_frame(s, 1, camera_at(2.0), turned, jobs);
    CHECK(work(p, LutKind::SkyView) == "-");
    CHECK(work(p, LutKind::AerialPerspective) == "sun");
  }
  SUBCASE("a camera climb rebuilds sky-view and AP; a short walk only AP") {
    const AtmospherePlan climb = run_frame(s, 1, camera_at(500.0), sun, jobs);
    CHECK(work(climb, LutKind::SkyView) == "camera");
    CHECK(work(climb, LutKind::AerialPerspective) == "camera");
    CHECK(work(climb, LutKind::Transmittance) == "-");
    const AtmospherePlan walk = run_frame(s, 2, camera_at(500.0, 200.0), sun, jobs);
    CHECK(work(walk, LutKind::SkyView) == "-");
    CHECK(work(walk, LutKind::AerialPerspective) == "camera");
    const AtmospherePlan turn = run_frame(s, 3, camera_at(500.0, 200.0, 30.0), sun, jobs);
    CHECK(work(turn, LutKind::SkyView) == "-");
    CHECK(work(turn, LutKind::AerialPerspective) == "camera");
  }
  SUBCASE("a parameter change rebuilds transmittance and everything downstream") {
    AtmosphereModel m;
    m.mie_scattering *= 2.0f;
    s.set_model(m);
    const AtmospherePlan p = run_frame(s, 1, camera_at(2.0), sun, jobs);
    CHECK(work(p, LutKind::Transmittance) == "params");
    CHECK(work(p, LutKind::MultiScattering) == "upstream");
    CHECK(work(p, LutKind::SkyView) == "upstream");
    CHECK(work(p, LutKind::AerialPerspective) == "upstream");
    CHECK(s.transmittance()->model() == m);
    CHECK(s.skyview() != nullptr);
    // Setting the same model again is not a change.
    s.set_model(m);
    const AtmospherePlan q = run_frame(s, 2, camera_at(2.0), sun, jobs);
    CHECK(work(q, LutKind::Transmittance) == "-");
  }
  SUBCASE("a parameter change chooses the multi-scattering LUT's explicit orders again") {
    CHECK(s.multiscattering()->explicit_orders() == explicit_orders_for(AtmosphereModel(), settings).orders);
    const AtmosphereModel dense = atmosphere_preset("earth-dense"), thin = atmosphere_preset("earth-thin");
    s.set_model(dense);
    run_frame(s, 1, camera_at(2.0), sun, jobs);
    CHECK(s.multiscattering()->explicit_orders() == settings.multiscattering_max_explicit_orders);
    s.set_model(thin);
    run_frame(s, 2, camera_at(2.0), sun, jobs);
    CHECK(s.multiscattering()->explicit_orders() == settings.multiscattering_explicit_orders);
  }
}

TEST_CASE("time slicing never exposes a half-updated LUT and ends bit-identical to a one-shot build") {
  JobSystem jobs(2);
  AtmosphereSettings settings = small_settings();
  settings.schedule[size_t(LutKind::SkyView)] = {8, 4};
  settings.schedule[size_t(LutKind::Transmittance)] = {16, 3};
  LutScheduler s(settings);
  const Camera cam = camera_at(2.0);
  run_frame(s, 0, cam, sun_from_zenith(40.0), jobs);  // initial: whole, in one frame
  CHECK(s.version(LutKind::SkyView) == 1);
  const std::shared_ptr<const SkyViewLut> old = s.skyview();
  const LutImage old_copy = old->image();

  const glm::vec3 sun2 = sun_from_zenith(60.0);
  for (int f = 1; f <= 4; ++f) {
    const AtmospherePlan p = run_frame(s, f, cam, sun2, jobs);
    const LutWork& w = p.work[size_t(LutKind::SkyView)];
    CHECK(w.active);
    CHECK(w.slice == f - 1);
    CHECK(w.slices == 4);
    CHECK(w.cause == "sun");
    if (f < 4) {
      // Still the old LUT, untouched.
      CHECK(s.skyview() == old);
      CHECK(same_bits(s.skyview()->image(), old_copy));
      CHECK(s.version(LutKind::SkyView) == 1);
    }
  }
  CHECK(s.version(LutKind::SkyView) == 2);
  CHECK(s.skyview() != old);
  CHECK(same_bits(old->image(), old_copy));  // a holder of the old LUT still sees it whole

  // A one-shot build with the same inputs gives the same bits.
  AtmosphereSettings full = settings;
  full.full_schedule = true;
  LutScheduler one_shot(full);
  run_frame(one_shot, 0, cam, sun2, jobs);
  CHECK(same_bits(one_shot.skyview()->image(), s.skyview()->image()));

  // A parameter change restarts the sliced transmittance; downstream keeps its consistent old set meanwhile.
  AtmosphereModel m;
  m.rayleigh_scattering *= 1.5f;
  s.set_model(m);
  const auto old_t = s.transmittance();
  for (int f = 5; f <= 7; ++f) {
    const AtmospherePlan p = run_frame(s, f, cam, sun2, jobs);
    CHECK(work(p, LutKind::Transmittance) == "params");
    CHECK(work(p, LutKind::MultiScattering) == (f == 7 ? "upstream" : "-"));
    if (f < 7) CHECK(s.transmittance() == old_t);
  }
  CHECK(s.transmittance()->model() == m);
  CHECK(s.multiscattering_source() == s.transmittance());
}

TEST_CASE("the full schedule rebuilds all four every frame") {
  JobSystem jobs(1);
  AtmosphereSettings settings = small_settings();
  settings.full_schedule = true;
  LutScheduler s(settings);
  for (int f = 0; f < 3; ++f) {
    const AtmospherePlan p = run_frame(s, f, camera_at(2.0), sun_from_zenith(30.0), jobs);
    for (int k = 0; k < kLutKinds; ++k) CHECK(work(p, LutKind(k)) == "full");
  }
  CHECK(s.version(LutKind::AerialPerspective) == 3);
  const nlohmann::json r = s.report(run_frame(s, 3, camera_at(2.0), sun_from_zenith(30.0), jobs));
  CHECK(r["skyview"]["updated"] == true);
  CHECK(r["skyview"]["cause"] == "full");
  CHECK(r["skyview"]["full_ms"].get<double>() >= 0.0);
  CHECK(r.contains("amortised_ms"));
}

TEST_CASE("above the space altitude the AP LUT is not built and the sky-view LUT is seen from space") {
  JobSystem jobs(1);
  LutScheduler s(small_settings());
  const AtmospherePlan p = run_frame(s, 0, camera_at(400e3), sun_from_zenith(30.0), jobs);
  CHECK(p.space);
  CHECK(work(p, LutKind::Transmittance) == "initial");
  CHECK(work(p, LutKind::SkyView) == "initial");
  CHECK(work(p, LutKind::AerialPerspective) == "-");
  CHECK(s.skyview()->mapping().first_angle > 1.5f);  // only directions that meet the atmosphere
  const SkyFrame f = frame_of(s, p, camera_at(400e3));
  CHECK(f.valid);
  // Looking down at the planet: lit ground and atmosphere; looking up: black space.
  const glm::vec3 down = sky_radiance(f, glm::vec3(0.3f, -0.95f, 0.0f) / glm::length(glm::vec3(0.3f, -0.95f, 0.0f)), false);
  const glm::vec3 up = sky_radiance(f, glm::vec3(0.0f, 1.0f, 0.0f), false);
  CHECK(down.y > 100.0f);
  CHECK(up == glm::vec3(0.0f));
  // Coming back down: the AP LUT is built and the sky-view LUT rebuilt for the new altitude.
  const AtmospherePlan back = run_frame(s, 1, camera_at(2.0), sun_from_zenith(30.0), jobs);
  CHECK(work(back, LutKind::SkyView) == "camera");
  CHECK(work(back, LutKind::AerialPerspective) == "initial");
  CHECK(s.skyview()->mapping().first_angle == 0.0f);
}

namespace {

// Sky in the upper half, geometry below at distances that need aerial perspective.
FrameBuffers sky_over_geometry(int w, int h) {
  FrameBuffers b;
  b.resize(w, h);
  for (int y = h / 2; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      b.depth[b.index(x, y)] = 0.5f;
      b.distance[b.index(x, y)] = 10.0f * float(x * x + y * 100);
      b.color[b.index(x, y)] = glm::vec3(100.0f);
    }
  return b;
}

}  // namespace

TEST_CASE("LUTs and composite are bit-identical for 1, 2 and 3 threads") {
  std::vector<std::vector<LutImage>> luts;
  std::vector<std::vector<glm::vec3>> images;
  AtmosphereSettings settings = small_settings();
  settings.schedule[size_t(LutKind::SkyView)] = {4, 2};
  for (unsigned threads : {1u, 2u, 3u}) {
    JobSystem jobs(threads);
    LutScheduler s(settings);
    AtmospherePlan p;
    for (int f = 0; f < 3; ++f) p = run_frame(s, f, camera_at(3.0 + f), sun_from_zenith(30.0 + 5.0 * f), jobs);
    luts.push_back({s.transmittance()->image(), s.multiscattering()->image(), s.skyview()->image(),
                    s.aerial_perspective()->luminance(), s.aerial_perspective()->transmittance()});
    const Camera cam = camera_at(5.0);
    const SkyFrame f = frame_of(s, p, cam);
    FrameBuffers b = sky_over_geometry(96, 54);
    jobs.parallel_for("composite", 6, 1, [&](size_t b0, size_t b1) {
      for (size_t t = b0; t < b1; ++t) composite_sky(f, b, int(t % 3) * 32, int(t / 3) * 27, int(t % 3) * 32 + 32, int(t / 3) * 27 + 27);
    });
    images.push_back(b.color);
  }
  for (size_t t = 1; t < luts.size(); ++t) {
    for (size_t k = 0; k < luts[0].size(); ++k) CHECK(same_bits(luts[0][k], luts[t][k]));
    CHECK(std::memcmp(images[0].data(), images[t].data(), images[0].size() * sizeof(glm::vec3)) == 0);
  }
}

TEST_CASE("the sky composite does not depend on how the frame is split") {
  JobSystem jobs(2);
  LutScheduler s(AtmosphereSettings{});  // full-size LUTs: most blocks are interpolated
  // Looking up, away from the sun: smooth sky, interpolated inside its blocks.
  const Camera cam =
      Camera::look_at(glm::dvec3(0.0, 5.0, 0.0), glm::dvec3(-1000.0, 800.0, 300.0), 1.0471976f, 16.0f / 9.0f, 0.1f);
  const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(60.0), jobs);
  const SkyFrame f = frame_of(s, p, cam);
  const FrameBuffers base = sky_over_geometry(160, 90);
  FrameBuffers whole = base;
  composite_sky(f, whole, 0, 0, 160, 90);
  // Rectangles starting at multiples of 8: tiles, and the composite pass's strips at 1 and 3 threads.
  FrameBuffers tiles = base;
  for (int y0 = 0; y0 < 90; y0 += 16)
    for (int x0 = 0; x0 < 160; x0 += 32) composite_sky(f, tiles, x0, y0, x0 + 32, std::min(y0 + 16, 90));
  CHECK(std::memcmp(whole.color.data(), tiles.color.data(), whole.color.size() * sizeof(glm::vec3)) == 0);
  for (unsigned threads : {1u, 3u}) {
    JobSystem strip_jobs(threads);
    FrameBuffers strips = base;
    for_each_composite_strip(strip_jobs, "composite", 160, 90,
                             [&](int x0, int y0, int x1, int y1) { composite_sky(f, strips, x0, y0, x1, y1); });
    CHECK(std::memcmp(whole.color.data(), strips.color.data(), whole.color.size() * sizeof(glm::vec3)) == 0);
  }
}

TEST_CASE("time slicing with spectral groups: the mixed LUT is the one its slices started, bit-identical to a one-shot build") {
  JobSystem jobs(2);
  AtmosphereSettings settings = small_settings();
  settings.spectral_samples = 6;
  settings.schedule[size_t(LutKind::SkyView)] = {8, 4};
  settings.schedule[size_t(LutKind::AerialPerspective)] = {8, 4};
  LutScheduler s(settings);
  const Camera cam = camera_at(2.0);
  run_frame(s, 0, cam, sun_from_zenith(40.0), jobs);
  // The sun moves 20 deg (a restart), then drifts below the threshold while the slices run.
  for (int f = 1; f <= 4; ++f) {
    const AtmospherePlan p = run_frame(s, f, cam, sun_from_zenith(60.0 + 0.1 * (f - 1)), jobs);
    CHECK(p.work[size_t(LutKind::SkyView)].slice == f - 1);
  }
  REQUIRE(s.version(LutKind::SkyView) == 2);
  REQUIRE(s.version(LutKind::AerialPerspective) == 2);
  AtmosphereSettings full = settings;
  full.full_schedule = true;
  LutScheduler one_shot(full);
  run_frame(one_shot, 0, cam, sun_from_zenith(60.0), jobs);
  CHECK(s.skyview()->mu_s() == one_shot.skyview()->mu_s());
  CHECK(same_bits(one_shot.skyview()->image(), s.skyview()->image()));
  CHECK(s.aerial_perspective()->camera().sun_direction == one_shot.aerial_perspective()->camera().sun_direction);
  CHECK(same_bits(one_shot.aerial_perspective()->luminance(), s.aerial_perspective()->luminance()));
}

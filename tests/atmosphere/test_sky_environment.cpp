// The sky's prefiltered specular environment: its schedule (initial bake,
// invalidation by sun and camera past the thresholds, none below them,
// periodic refresh, time slicing behind a double buffer), determinism, the
// ground below the horizon, publishing to the lighting, and its profile fields.
#include <doctest/doctest.h>

#include <string>

#include "atmosphere/sky_composite.h"
#include "atmosphere/sky_environment.h"
#include "atmosphere/sky_lighting.h"
#include "atmosphere_test_util.h"
#include "engine/core/error.h"

using namespace cr;
using namespace cr::test;

namespace {

AtmosphereSettings env_settings() {
  AtmosphereSettings s = small_settings();
  s.environment_size = 16;
  s.environment_levels = 4;
  s.environment_samples = 8;
  s.environment_schedule = {8, 4};
  return s;
}

// One frame as the plugin runs it: the LUTs, then the environment from the frame's sky.
struct EnvCase {
  LutScheduler luts;
  SkyEnvironment env;
  explicit EnvCase(const AtmosphereSettings& s) : luts(s), env(s) {}
  EnvironmentWork frame(int f, const Camera& cam, const glm::vec3& sun, JobSystem& jobs) {
    const AtmospherePlan p = run_frame(luts, f, cam, sun, jobs);
    const uint64_t upstream = luts.version(LutKind::MultiScattering);
    const EnvironmentWork w = env.plan(p, upstream);
    env.run(w, p, upstream, frame_of(luts, p, cam), jobs);
    return w;
  }
};

std::string cause(const EnvironmentWork& w) { return w.active ? w.cause : "-"; }

bool same(const SpecularEnvironment& a, const SpecularEnvironment& b) {
  if (a.levels() != b.levels()) return false;
  for (int k = 0; k < a.levels(); ++k)
    for (int y = 0; y < a.size(k); ++y)
      for (int x = 0; x < a.size(k); ++x)
        if (a.texel(k, x, y) != b.texel(k, x, y)) return false;
  return true;
}

}  // namespace

TEST_CASE("sky environment: the first frame bakes it whole; unchanged inputs never rebake") {
  JobSystem jobs(2);
  EnvCase c(env_settings());
  const Camera cam = camera_at(2.0);
  const glm::vec3 sun = sun_from_zenith(40.0);
  const EnvironmentWork w0 = c.frame(0, cam, sun, jobs);
  CHECK(cause(w0) == "initial");
  CHECK(w0.slices == 1);
  CHECK(w0.publishes);
  REQUIRE(c.env.front());
  CHECK(c.env.version() == 1);
  const auto first = c.env.front();
  for (int f = 1; f < 40; ++f) CHECK(cause(c.frame(f, cam, sun, jobs)) == "-");
  CHECK(c.env.front() == first);
  const nlohmann::json r = c.env.report(EnvironmentWork{}, 39);
  CHECK(r["age_frames"] == 39);
  CHECK(r["updated"] == false);
}

TEST_CASE("sky environment: invalidation past the thresholds, none below them, periodic refresh") {
  JobSystem jobs(2);
  const AtmosphereSettings s = env_settings();
  EnvCase c(s);
  const glm::vec3 sun = sun_from_zenith(40.0);
  c.frame(0, camera_at(2.0), sun, jobs);

  SUBCASE("a sun move below the threshold waits for the period") {
    const glm::vec3 moved = sun_from_zenith(40.3);  // 0.3 deg < 0.5
    for (int f = 1; f < 8; ++f) CHECK(cause(c.frame(f, camera_at(2.0), moved, jobs)) == "-");
    CHECK(cause(c.frame(8, camera_at(2.0), moved, jobs)) == "periodic");
  }
  SUBCASE("a sun move past the threshold rebakes at once, in azimuth too") {
    CHECK(cause(c.frame(1, camera_at(2.0), sun_from_zenith(41.0), jobs)) == "sun");
    EnvCase d(s);
    d.frame(0, camera_at(2.0), sun, jobs);
    const glm::vec3 turned = glm::vec3(sun.x * std::cos(0.05f), sun.y, sun.x * std::sin(0.05f));  // ~1.8 deg
    CHECK(cause(d.frame(1, camera_at(2.0), turned, jobs)) == "sun");
  }
  SUBCASE("a camera climb past the threshold rebakes; a short walk or a turn does not") {
    CHECK(cause(c.frame(1, camera_at(2.0, 30.0, 40.0), sun, jobs)) == "-");
    CHECK(cause(c.frame(2, camera_at(40.0), sun, jobs)) == "-");  // 38 m < 50 m
    CHECK(cause(c.frame(3, camera_at(200.0), sun, jobs)) == "camera");
  }
  SUBCASE("the atmosphere changing rebakes it as upstream") {
    AtmosphereModel hazy;
    hazy.mie_scattering *= 10.0f;
    c.luts.set_model(hazy);
    EnvironmentWork w;
    for (int f = 1; f < 4 && !w.active; ++f) w = c.frame(f, camera_at(2.0), sun, jobs);
    CHECK(cause(w) == "upstream");
  }
}

TEST_CASE("sky environment: time slicing completes within the period and publishes atomically") {
  JobSystem jobs(2);
  const AtmosphereSettings s = env_settings();
  EnvCase c(s);
  c.frame(0, camera_at(2.0), sun_from_zenith(40.0), jobs);
  const auto before = c.env.front();
  const glm::vec3 sun = sun_from_zenith(45.0);
  // The rebuild takes `slices` frames; the front stays the old, complete one until the last.
  for (int f = 1; f <= s.environment_schedule.slices; ++f) {
    const EnvironmentWork w = c.frame(f, camera_at(2.0), sun, jobs);
    CAPTURE(f);
    CHECK(w.active);
    CHECK(w.cause == "sun");
    CHECK(w.slice == f - 1);
    CHECK(w.publishes == (f == s.environment_schedule.slices));
    CHECK((c.env.front() == before) == (f < s.environment_schedule.slices));
  }
  CHECK(c.env.version() == 2);
  CHECK(s.environment_schedule.slices <= s.environment_schedule.period);
  // The sliced result is the one-shot bake of the frame it started from, bit for bit.
  const AtmospherePlan p = run_frame(c.luts, 5, camera_at(2.0), sun, jobs);
  const auto whole = bake_sky_environment(frame_of(c.luts, p, camera_at(2.0)), s, jobs);
  CHECK(same(*whole, *c.env.front()));
  // A further sun move during a rebuild does not restart it: it finishes, then the next starts.
  c.frame(6, camera_at(2.0), sun_from_zenith(50.0), jobs);
  const EnvironmentWork mid = c.frame(7, camera_at(2.0), sun_from_zenith(55.0), jobs);
  CHECK(mid.slice == 1);
  CHECK(!mid.restart);
}

TEST_CASE("sky environment: the bake is bit-identical for 1 and 3 threads; the ground lies below the horizon") {
  const AtmosphereSettings s = env_settings();
  JobSystem one(1), three(3);
  LutScheduler luts(s);
  const AtmospherePlan p = run_frame(luts, 0, camera_at(2.0), sun_from_zenith(40.0), one);
  const SkyFrame f = frame_of(luts, p, camera_at(2.0));
  const auto a = bake_sky_environment(f, s, one), b = bake_sky_environment(f, s, three);
  CHECK(same(*a, *b));
  // Level 0 is the sky-view LUT's radiance, the sun-lit ground below the horizon included.
  const glm::vec3 nadir = a->sample_level(glm::vec3(0, -1, 0), 0.0f);
  CHECK(nadir.g > 0.0f);
  CHECK(glm::length(nadir - sky_radiance(f, glm::vec3(0, -1, 0), false)) < 0.02f * glm::length(nadir));
  // Published with the rest of the lighting.
  LightEnvironment light;
  fill_light_environment(f, light, a);
  CHECK(light.specular == a);
}

TEST_CASE("sky environment: bad profile values give errors naming the file and the field") {
  auto message = [](const nlohmann::json& j) {
    try {
      parse_atmosphere_settings(j, "p.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const AtmosphereSettings d = parse_atmosphere_settings(nlohmann::json(), "p.json");
  CHECK(d.environment_size == 64);
  CHECK(d.environment_schedule.slices <= d.environment_schedule.period);
  const AtmosphereSettings s = parse_atmosphere_settings({{"environment", {{"size", 32}, {"period", 120}}}}, "p.json");
  CHECK(s.environment_size == 32);
  CHECK(s.environment_schedule.period == 120);
  for (const auto& [j, field] : std::vector<std::pair<nlohmann::json, std::string>>{
           {{{"environment", {{"size", 48}}}}, "atmosphere.environment.size"},
           {{{"environment", {{"size", 512}}}}, "atmosphere.environment.size"},
           {{{"environment", {{"levels", 0}}}}, "atmosphere.environment.levels"},
           {{{"environment", {{"samples", 5000}}}}, "atmosphere.environment.samples"},
           {{{"environment", {{"period", 2}, {"slices", 4}}}}, "atmosphere.environment.slices"},
           {{{"environment", {{"sizes", 4}}}}, "atmosphere.environment.sizes: unknown key"},
           {{{"environment", 3}}, "atmosphere.environment"}}) {
    CAPTURE(field);
    const std::string m = message(j);
    CHECK(m.find("p.json") != std::string::npos);
    CHECK(m.find(field) != std::string::npos);
  }
}

// Multi-scattering against a brute-force evaluation, the composite and the
// lighting's physical sanity, and the stability sweep.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/tools/reference_renderer.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere/sky_lighting.h"
#include "atmosphere_test_util.h"
#include "engine/core/luminance.h"
#include "engine/core/math_constants.h"

using namespace cr;
using namespace cr::test;

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Sum of sigma_s * T along a ray from altitude h with zenith cosine cos_p to the top, fine steps.
glm::dvec3 unit_field_luminance(const AtmosphereModel& m, double h, double cos_p, int steps) {
  const double R = m.bottom_radius, r0 = R + h;
  const double dt = distance_to_sphere_exit(r0, cos_p, m.top_radius) / steps;
  glm::dvec3 throughput(1.0), f(0.0);
  for (int k = 0; k < steps; ++k) {
    const double t = (k + 0.5) * dt;
    const MediumSample med = sample_medium(m, float(std::sqrt(r0 * r0 + t * t + 2.0 * r0 * t * cos_p) - R));
    const glm::dvec3 ext(med.extinction);
    f += throughput * glm::dvec3(med.scattering) * (glm::dvec3(1.0) - glm::exp(-ext * dt)) / ext;
    throughput *= glm::exp(-ext * dt);
  }
  return f;
}

// The second-order field L2 (sphere mean) at one point by brute force, the
// sun's light scattered by the true phase: many directions, fine steps and
// the sun's transmittance marched directly (no LUT). (f_ms, which includes
// the ground reflecting the unit isotropic field back, is computed alongside.)
glm::vec3 brute_force_psi(const AtmosphereModel& m, double altitude, double mu_s) {
  const int n = 40;  // n*n directions, independent of the LUT's stratification
  const int steps = 60;
  const double R = m.bottom_radius;
  glm::dvec3 ground_irradiance(0.0);  // from the unit field: integral of L cos over the upper hemisphere
  for (int b = 0; b < 400; ++b) {
    const double cos_p = (b + 0.5) / 400.0;
    ground_irradiance += unit_field_luminance(m, 0.0, cos_p, 400) * cos_p * (2.0 * kPiD / 400.0);
  }
  const glm::dvec3 x0(0.0, R + altitude, 0.0);
  const glm::dvec3 s(std::sqrt(1.0 - mu_s * mu_s), mu_s, 0.0);
  auto direction = [&](int a, int b) {
    const double cos_p = 1.0 - 2.0 * (b + 0.37) / n;
    const double phi = 2.0 * kPiD * (a + 0.61) / n;
    const double sin_p = std::sqrt(1.0 - cos_p * cos_p);
    return glm::dvec3(sin_p * std::cos(phi), cos_p, sin_p * std::sin(phi));
  };
  // Each phase normalised over the directions, as the LUT does (a forward peak
  // between directions would otherwise gain or lose energy).
  double mean_r = 0.0, mean_m = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const float c = float(glm::dot(direction(a, b), s));
      mean_r += rayleigh_phase(c) * 4.0 * kPiD / double(n * n);
      mean_m += mie_phase(m, c) * 4.0 * kPiD / double(n * n);
    }
  glm::dvec3 l2(0.0), fms(0.0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const glm::dvec3 d = direction(a, b);
      const double cos_p = d.y;
      const double r0 = R + altitude;
      const double tg = distance_to_ground(r0, cos_p, R);
      const double t_max = tg >= 0.0 ? tg : distance_to_sphere_exit(r0, cos_p, m.top_radius);
      const double dt = t_max / steps;
      glm::dvec3 throughput(1.0), l(0.0), f(0.0);
      for (int k = 0; k < steps; ++k) {
        const glm::dvec3 p = x0 + d * ((k + 0.5) * dt);
        const MediumSample med = sample_medium(m, float(glm::length(p) - R));
        const glm::dvec3 ext(med.extinction), sca(med.scattering);
        const glm::dvec3 seg = (glm::dvec3(1.0) - glm::exp(-ext * dt)) / ext;
        const glm::dvec3 sun = reference_transmittance(m, p, s);
        const float c = float(glm::dot(d, s));
        const glm::dvec3 phased = glm::dvec3(med.rayleigh_scattering) * (double(rayleigh_phase(c)) / mean_r) +
                                  glm::dvec3(med.mie_scattering) * (double(mie_phase(m, c)) / mean_m);
        l += throughput * phased * seg * sun;
        f += throughput * sca * seg;
        throughput *= glm::exp(-ext * dt);
      }
      if (tg >= 0.0) {
        const glm::dvec3 pg = x0 + d * tg;
        const double mu_g = glm::dot(glm::normalize(pg), s);
        if (mu_g > 0.0)
          l += throughput * glm::dvec3(m.ground_albedo) / kPiD * reference_transmittance(m, pg, s) * mu_g;
        f += throughput * glm::dvec3(m.ground_albedo) / kPiD * ground_irradiance;
      }
      l2 += l;
      fms += f;
    }
  l2 /= double(n * n);
  fms /= double(n * n);
  return glm::vec3(l2);
}

}  // namespace

TEST_CASE("multi-scattering LUT matches a brute-force evaluation of its integrals") {
  const AtmosphereModel m;
  TransmittanceLut t(m, 256, 64, 40);
  t.bake(0, t.texel_count());
  MultiScatteringLut ms(m, 32, 32, 64, 20, 0.95f, 1);
  ms.bake(0, ms.work_items(), t);
  // Relative, per channel (doctest's default scale of 1 made epsilon absolute: no check at Psi ~ 0.05).
  // Sun high or air above the ground: within 10%. The ground under a low sun is the hardest case for
  // 64 directions (bright, very long rays just above the horizon, the ground just below): the LUT is
  // still up to ~20% low there (uniform in cos, without the ground's share of f_ms, it was lower).
  struct Point {
    double h, mu_s, tolerance;
  };
  for (const Point p : {Point{0.0, 1.0, 0.10}, Point{3300.0, 1.0, 0.10}, Point{3000.0, 0.6, 0.10}, Point{10000.0, 0.07, 0.10},
                        Point{0.0, 0.2, 0.20}, Point{0.0, 0.0, 0.22}}) {
    // Texel-centred points: h = j/31 * 100 km, mu_s at unit x = i/31.
    const double hh = std::round(p.h / (100e3 / 31.0)) * (100e3 / 31.0);
    const double mm = MultiScatteringMapping::from_unit(
        float(std::round(MultiScatteringMapping::to_unit(float(p.mu_s)) * 31.0) / 31.0));
    const glm::vec3 lut = ms.second_order(float(hh), float(mm));
    const glm::vec3 ref = brute_force_psi(m, hh, mm);
    CAPTURE(hh);
    CAPTURE(mm);
    for (int c = 0; c < 3; ++c) CHECK(lut[c] == doctest::Approx(ref[c]).epsilon(p.tolerance).scale(0.0));
  }
  // Midway between columns in Earth's shadow, where Psi falls exponentially with mu_s (h = 0: on a row).
  // Interpolated over 32 uniform columns it was 2-3x too high here; the LUT is ~10-15% low, as above.
  for (double mu_s : {-0.065, -0.09}) {
    const glm::vec3 lut = ms.second_order(0.0f, float(mu_s));
    const glm::vec3 ref = brute_force_psi(m, 0.0, mu_s);
    CAPTURE(mu_s);
    for (int c = 0; c < 3; ++c) CHECK(lut[c] == doctest::Approx(ref[c]).epsilon(0.20).scale(0.0));
  }
  CHECK(ms.clamped_texels() == 0);
  CHECK(ms.max_fms_seen() > 0.05f);
  CHECK(ms.max_fms_seen() < 0.6f);
}

TEST_CASE("the explicit orders follow f_ms: none for thin air, the most for dense air") {
  struct Case {
    const char* preset;
    int orders;
  };
  for (const Case c : {Case{"earth-thin", 0}, Case{"earth-clear", 1}, Case{"earth-dense", 4}}) {
    const AtmosphereModel m = atmosphere_preset(c.preset);
    const ExplicitOrderChoice choice = explicit_orders_for(m, 16, 64, 20, 0.95f, 0, 4, 0.15f);
    CAPTURE(c.preset);
    CHECK(choice.orders == c.orders);
    // The estimate is the f_ms the bake finds (same rows, same march).
    TransmittanceLut t(m, 128, 32, 40);
    t.bake(0, t.texel_count());
    MultiScatteringLut ms(m, 16, 16, 64, 20, 0.95f, 0);
    ms.bake(0, ms.work_items(), t);
    CHECK(choice.max_fms == doctest::Approx(ms.max_fms_seen()).epsilon(1e-6));
    // The fewest orders whose series share is within the tolerance, unless capped.
    const double share = std::pow(double(choice.max_fms), choice.orders + 1);
    CHECK((share <= 0.15 || choice.orders == 4));
    if (choice.orders > 0) CHECK(std::pow(double(choice.max_fms), choice.orders) > 0.15);
    // A tail share of 1 keeps the minimum; a minimum above the choice wins.
    CHECK(explicit_orders_for(m, 16, 64, 20, 0.95f, 0, 4, 1.0f).orders == 0);
    CHECK(explicit_orders_for(m, 16, 64, 20, 0.95f, 5, 8, 0.15f).orders >= 5);
  }
}

TEST_CASE("in dense air, the chosen explicit orders take Psi most of the way to the converged series") {
  const AtmosphereModel m = atmosphere_preset("earth-dense");
  TransmittanceLut t(m, 128, 32, 40);
  t.bake(0, t.texel_count());
  auto psi = [&](int orders) {
    MultiScatteringLut ms(m, 16, 16, 64, 20, 0.95f, orders);
    ms.bake(0, ms.work_items(), t);
    return ms;
  };
  const int chosen = explicit_orders_for(m, 16, 64, 20, 0.95f, 0, 4, 0.15f).orders;
  const MultiScatteringLut one = psi(1), auto_orders = psi(chosen), many = psi(10);
  // Mean relative distance to the 10-order LUT over lit texels (the sun above the horizon).
  double d_one = 0.0, d_auto = 0.0;
  int n = 0;
  for (float h : {0.0f, 2000.0f, 8000.0f})
    for (float mu_s : {0.1f, 0.5f, 1.0f}) {
      const glm::vec3 ref = many.sample(h, mu_s);
      d_one += std::abs(luminance(one.sample(h, mu_s)) / luminance(ref) - 1.0f);
      d_auto += std::abs(luminance(auto_orders.sample(h, mu_s)) / luminance(ref) - 1.0f);
      ++n;
    }
  d_one /= n;
  d_auto /= n;
  CAPTURE(d_one);
  CAPTURE(d_auto);
  CHECK(chosen == 4);
  CHECK(d_auto < 0.5 * d_one);
  CHECK(d_one > 0.02);  // one order is visibly off here, or the test says nothing
}

TEST_CASE("sky colours, sun disk and aerial perspective are physically sensible") {
  JobSystem jobs(2);
  LutScheduler s(small_settings());
  const Camera cam = camera_at(2.0);
  SUBCASE("noon: blue zenith, bright halo around the sun, sun disk attenuated but bright") {
    const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(30.0), jobs);
    const SkyFrame f = frame_of(s, p, cam);
    const glm::vec3 zenith = sky_radiance(f, glm::vec3(0, 1, 0), false);
    CHECK(zenith.z > zenith.x * 1.5f);
    CHECK(luminance(zenith) > 1000.0f);   // a clear sky is some 10^3..10^4 cd/m^2
    CHECK(luminance(zenith) < 20000.0f);
    const glm::vec3 near_sun = glm::normalize(f.sun + glm::vec3(0.0f, 0.0f, 0.05f));
    const glm::vec3 away = glm::normalize(glm::vec3(-f.sun.x, f.sun.y, 0.3f));
    CHECK(luminance(sky_radiance(f, near_sun, false)) > 2.0f * luminance(sky_radiance(f, away, false)));
    const glm::vec3 disk = sky_radiance(f, f.sun, true) - sky_radiance(f, f.sun, false);
    CHECK(luminance(disk) > 1e8f);
    CHECK(luminance(disk) < 2e9f);
    // Limb darkening: the edge of the disk is darker than its centre.
    const float edge = 0.95f * f.model.sun_angular_radius;
    const glm::vec3 to_edge = glm::normalize(f.sun + glm::vec3(0.0f, 0.0f, std::tan(edge)));
    CHECK(luminance(sun_disk_radiance(f, to_edge)) < 0.8f * luminance(sun_disk_radiance(f, f.sun)));
    // Aerial perspective: far objects fade (T < 1) and gain in-scattered light; near ones barely change.
    const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, -0.01f, 0.2f));
    const glm::vec3 black_far = apply_aerial_perspective(f, dir, 50000.0f, glm::vec3(0.0f));
    const glm::vec3 black_near = apply_aerial_perspective(f, dir, 10.0f, glm::vec3(0.0f));
    CHECK(luminance(black_far) > 100.0f * luminance(black_near));
    const glm::vec3 white_far = apply_aerial_perspective(f, dir, 50000.0f, glm::vec3(1000.0f));
    CHECK(white_far.z - black_far.z < white_far.x - black_far.x);  // blue is extinguished more than red
    // Beyond the froxel range the march continues smoothly.
    const float range = f.aerial_perspective->range();
    const float a = luminance(apply_aerial_perspective(f, dir, range * 0.999f, glm::vec3(0.0f)));
    const float b = luminance(apply_aerial_perspective(f, dir, range * 1.001f, glm::vec3(0.0f)));
    CHECK(b == doctest::Approx(a).epsilon(0.02));
  }
  SUBCASE("sunset: reddened sun, darker sky; night: no sun light at all") {
    const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(89.0), jobs);
    const SkyFrame f = frame_of(s, p, cam);
    LightEnvironment light;
    fill_light_environment(f, light);
    CHECK(light.sun_illuminance.x > light.sun_illuminance.z * 2.0f);
    CHECK(light.sun_illuminance.x < 110000.0f * 0.5f);
    const AtmospherePlan n = run_frame(s, 1, cam, sun_from_zenith(120.0), jobs);
    const SkyFrame night = frame_of(s, n, cam);
    LightEnvironment dark;
    fill_light_environment(night, dark);
    CHECK(dark.sun_illuminance == glm::vec3(0.0f));
    CHECK(sun_illuminance_at(dark, glm::vec3(100.0f, 0.0f, 50.0f)) == glm::vec3(0.0f));
    CHECK(luminance(sky_radiance(night, glm::vec3(0, 1, 0), true)) < 1e-3f * 110000.0f);
  }
  SUBCASE("lighting: sun_at follows altitude, ambient SH is the sky's mean radiance") {
    const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(60.0), jobs);
    const SkyFrame f = frame_of(s, p, cam);
    LightEnvironment light;
    fill_light_environment(f, light);
    const glm::vec3 ground = sun_illuminance_at(light, glm::vec3(0.0f));
    const glm::vec3 peak = sun_illuminance_at(light, glm::vec3(0.0f, 8000.0f, 0.0f));
    CHECK(peak.z > ground.z);  // less air above a mountain top
    CHECK(ground.x == doctest::Approx(light.sun_illuminance.x).epsilon(0.01));
    // Y00 * c00 is the sphere-mean radiance: compare with a direct average of the sky.
    glm::vec3 mean(0.0f);
    const int n = 64;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 2 * n; ++j) {
        const float ct = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
        const float st = std::sqrt(1.0f - ct * ct);
        const float ph = kPi * (float(j) + 0.5f) / float(n);
        mean += sky_radiance(f, glm::vec3(st * std::cos(ph), ct, st * std::sin(ph)), false);
      }
    mean /= float(2 * n * n);
    for (int c = 0; c < 3; ++c) CHECK(light.ambient_sh[0][c] * 0.282095f == doctest::Approx(mean[c]).epsilon(0.05));
  }
}

TEST_CASE("stability sweep: finite, bounded outputs everywhere") {
  JobSystem jobs(2);
  struct Variant {
    const char* name;
    AtmosphereModel model;
  };
  std::vector<Variant> variants;
  variants.push_back({"earth", AtmosphereModel()});
  for (float scale : {0.01f, 100.0f}) {
    AtmosphereModel m;
    m.rayleigh_scattering *= scale;
    m.mie_scattering *= scale;
    m.mie_absorption *= scale;
    m.ozone_absorption *= scale;
    variants.push_back({scale < 1.0f ? "density x0.01" : "density x100", m});
  }
  for (float g : {-0.99f, 0.99f}) {
    AtmosphereModel m;
    m.mie_g = g;
    m.mie_scattering *= 10.0f;
    variants.push_back({g < 0.0f ? "mie g -0.99" : "mie g 0.99", m});
  }
  {
    AtmosphereModel m;
    m.rayleigh_scattering *= 100.0f;  // scattering-only: f_ms -> 1
    m.ozone_absorption = glm::vec3(0.0f);
    m.mie_absorption = glm::vec3(0.0f);
    m.ground_albedo = glm::vec3(1.0f);
    variants.push_back({"conservative dense", m});
  }
  const std::vector<double> zeniths{0.0, 45.0, 89.5, 95.0, 135.0, 180.0};
  const std::vector<double> altitudes{-50.0, 0.05, 1.0, 3000.0, 99e3, 150e3, 1e6};
  std::vector<glm::vec3> dirs;
  for (int i = 0; i < 24; ++i) {
    const float e = (90.0f - 180.0f * (float(i) + 0.5f) / 24.0f) * kPi / 180.0f;
    const float a = float(i) * 2.1f;
    dirs.push_back(glm::vec3(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)));
  }
  for (const Variant& v : variants)
  for (bool fixed : {false, true}) {  // desktop's float path and mobile's q15 LUTs with the fixed-point composite
    AtmosphereSettings settings = small_settings();
    settings.full_schedule = true;
    if (fixed) {
      settings.lut_precision = LutPrecision::Q15;
      settings.composite_precision = CompositePrecision::Fixed;
    }
    LutScheduler s(settings);
    s.set_model(v.model);
    int frame = 0;
    for (double alt : altitudes)
      for (double zen : zeniths) {
        CAPTURE(v.name);
        CAPTURE(fixed);
        CAPTURE(alt);
        CAPTURE(zen);
        const Camera cam = camera_at(alt);
        const AtmospherePlan p = run_frame(s, frame++, cam, sun_from_zenith(zen), jobs);
        const SkyFrame f = frame_of(s, p, cam);
        REQUIRE(f.valid);
        for (const glm::vec3& d : dirs) {
          const glm::vec3 l = sky_radiance(f, d, true);
          CHECK(finite(l));
          CHECK(glm::all(glm::greaterThanEqual(l, glm::vec3(0.0f))));
          CHECK(luminance(sky_radiance(f, d, false)) < 2e6f);  // bounded (sun disk excluded)
          for (float dist : {1.0f, 500.0f, 60000.0f, 400000.0f}) {
            const glm::vec3 c = apply_aerial_perspective(f, d, dist, glm::vec3(1000.0f));
            CHECK(finite(c));
            CHECK(glm::all(glm::greaterThanEqual(c, glm::vec3(0.0f))));
          }
        }
        LightEnvironment light;
        fill_light_environment(f, light);
        CHECK(finite(light.sun_illuminance));
        for (const glm::vec3& c : light.ambient_sh) CHECK(finite(c));
        for (const glm::vec3& t : s.aerial_perspective() ? s.aerial_perspective()->transmittance().texels
                                                         : std::vector<glm::vec3>{})
          CHECK(glm::all(glm::lessThanEqual(t, glm::vec3(1.0f))));
      }
    if (std::string(v.name) == "conservative dense") {
      CHECK(s.multiscattering()->clamped_texels() > 0);  // f_ms clamped, and reported
      CHECK(s.report(run_frame(s, frame, camera_at(1.0), sun_from_zenith(30.0), jobs))["multiscattering_clamped_texels"]
                .get<int>() > 0);
    }
  }
}

TEST_CASE("the sky is smooth across the horizon and around the zenith") {
  JobSystem jobs(1);
  LutScheduler s(AtmosphereSettings{});
  const Camera cam = camera_at(2.0);
  const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(60.0), jobs);
  const SkyFrame f = frame_of(s, p, cam);
  // Elevation sweep above the horizon: neighbouring samples (0.25 deg apart) never jump.
  float prev = -1.0f;
  for (int i = 4; i < 360; ++i) {
    const float e = float(i) * 0.25f * kPi / 180.0f;
    const float l = luminance(sky_radiance(f, glm::vec3(-std::cos(e), std::sin(e), 0.0f) , false));
    if (prev > 0.0f) CHECK(std::abs(l - prev) < 0.08f * prev);
    prev = l;
  }
}

namespace {

// The per-pixel luminance error of the composite against sky_radiance / apply_aerial_perspective per pixel.
struct CompositeCheck {
  double sky_max = 0.0, sky_mean = 0.0, ap_max = 0.0;
  int sky = 0, ap = 0, disk = 0;
  int fragment_mismatches = 0;  // edge-pixel fragments off their definition
};

CompositeCheck check_composite(const SkyFrame& f, const Camera& cam, int w, int h, float ground_distance) {
  FrameBuffers b;
  b.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 d = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, w, h);
      const size_t i = b.index(x, y);
      if (ground_distance > 0.0f && d.y < -0.02f) {
        b.depth[i] = 0.5f;
        b.distance[i] = ground_distance * float(1 + x % 7);
        b.color[i] = glm::vec3(500.0f, 400.0f, 300.0f);
      }
    }
  const FrameBuffers before = b;
  for (int y0 = 0; y0 < h; y0 += 64)
    for (int x0 = 0; x0 < w; x0 += 64) composite_sky(f, b, x0, y0, std::min(w, x0 + 64), std::min(h, y0 + 64));
  CompositeCheck c;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = b.index(x, y);
      const glm::vec3 d = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, w, h);
      const bool sky = before.depth[i] == 0.0f;
      const glm::vec3 expect = sky ? sky_radiance(f, d, true) : apply_aerial_perspective(f, d, before.distance[i], before.color[i]);
      const double ref = luminance(expect);
      const double err = std::abs(luminance(b.color[i]) - ref) / std::max(ref, 1e-3);
      if (sky) {
        c.sky_max = std::max(c.sky_max, err);
        c.sky_mean += err;
        ++c.sky;
        c.disk += sun_disk_radiance(f, d) != glm::vec3(0.0f) ? 1 : 0;
      } else {
        c.ap_max = std::max(c.ap_max, err);
        ++c.ap;
      }
    }
  c.sky_mean /= std::max(c.sky, 1);
  // Edge-pixel fragments: the definitions at their own position and
  // distance, the sky where nothing was drawn.
  std::vector<EdgeFragment> fragments;
  for (int k = 0; k < 400; ++k) {
    const int x = (k * 37) % w, y = (k * 53) % h;
    const size_t i = before.index(x, y);
    EdgeFragment e;
    e.pixel = uint32_t(i);
    e.x = float(x) + 0.25f + 0.5f * float(k % 3) / 2.0f;
    e.y = float(y) + 0.75f - 0.5f * float(k % 5) / 4.0f;
    e.depth = before.depth[i];
    e.distance = before.distance[i] * (k % 2 ? 0.5f : 1.0f);
    e.color = before.color[i];
    fragments.push_back(e);
  }
  std::vector<EdgeFragment> composited = fragments;
  composite_sky_fragments(f, w, h, composited);
  for (size_t k = 0; k < fragments.size(); ++k) {
    const EdgeFragment& e = fragments[k];
    const glm::vec3 d = cam.ray_direction(e.x, e.y, w, h);
    const glm::vec3 expect =
        e.depth == 0.0f ? sky_radiance(f, d, true) : apply_aerial_perspective(f, d, e.distance, e.color);
    c.fragment_mismatches += composited[k].color != expect;
  }
  return c;
}

}  // namespace

TEST_CASE("the composite matches per-pixel evaluation (sky interpolated in blocks, sun disk, froxels)") {
  JobSystem jobs(1);
  AtmosphereSettings settings;
  double ap_tolerance = 1e-3;
  SUBCASE("float") {}
  SUBCASE("q15 LUTs, fixed-point composite") {
    settings.lut_precision = LutPrecision::Q15;
    settings.composite_precision = CompositePrecision::Fixed;
    // The kernel's and the definition's froxel weights are computed by
    // different float operations; rounded to q15 they may differ by one
    // code, and the result by one code of the brightest froxel (here 1.3
    // cd/m^2 on surfaces of about 800).
    ap_tolerance = 2e-3;
  }
  LutScheduler s(settings);
  // Looking towards a low sun: horizon, halo and disk in view.
  const Camera cam = Camera::look_at(glm::dvec3(0.0, 2.0, 0.0), glm::dvec3(1000.0, 60.0, 20.0), 1.0471976f,
                                     16.0f / 9.0f, 0.1f);
  const AtmospherePlan p = run_frame(s, 0, cam, glm::normalize(glm::vec3(1.0f, 0.08f, 0.0f)), jobs);
  const SkyFrame f = frame_of(s, p, cam);
  const CompositeCheck c = check_composite(f, cam, 320, 180, 700.0f);
  CAPTURE(c.sky_max);
  CAPTURE(c.sky_mean);
  CAPTURE(c.ap_max);
  MESSAGE("composite vs per pixel: sky mean " << c.sky_mean << ", sky max " << c.sky_max << ", AP max " << c.ap_max);
  CHECK(c.sky > 10000);
  CHECK(c.ap > 10000);
  CHECK(c.disk > 0);
  CHECK(c.fragment_mismatches == 0);
  CHECK(c.sky_mean < 1e-3);
  CHECK(c.sky_max < 0.01);  // the interpolation's worst pixel
  CHECK(c.ap_max < ap_tolerance);
}

TEST_CASE("from space the sky-view LUT matches the per-pixel ray march it replaces") {
  JobSystem jobs(1);
  LutScheduler s(AtmosphereSettings{});
  const Camera cam = Camera::look_at(glm::dvec3(0.0, 400e3, 0.0), glm::dvec3(2200e3, 0.0, 0.0), 1.0471976f,
                                     16.0f / 9.0f, 1.0f);
  const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(70.0), jobs);
  REQUIRE(p.space);
  const SkyFrame f = frame_of(s, p, cam);
  const AtmosphereLuts luts{f.model, *f.ms_transmittance, *f.multiscattering};
  MarchedRay scratch;
  double sum = 0.0;
  std::vector<double> errors;
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 160; ++x) {
      const glm::vec3 d = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, 160, 90);
      const double mu = glm::dot(glm::dvec3(d), f.camera_position / glm::length(f.camera_position));
      const RayScattering ref = integrate_ray(luts, f.camera_radius, mu, f.mu_s, glm::dot(d, f.sun), 1e30,
                                              f.skyview_min_steps, f.space_steps, scratch);
      const double yr = luminance(ref.luminance * f.sun_illuminance);
      if (yr < 1.0) continue;  // space, and the planet's night side
      const double e = std::abs(luminance(sky_radiance(f, d, false)) - yr) / yr;
      errors.push_back(e);
      sum += e;
    }
  REQUIRE(errors.size() > 5000);
  std::sort(errors.begin(), errors.end());
  const double mean = sum / double(errors.size()), p95 = errors[errors.size() * 95 / 100];
  CAPTURE(mean);
  CAPTURE(p95);
  MESSAGE("space sky-view LUT vs per-pixel march: mean " << mean << ", p95 " << p95);
  CHECK(mean < 0.01);
  CHECK(p95 < 0.03);
}

TEST_CASE("batched sky radiance equals sky_radiance without the disk, bit for bit") {
  JobSystem jobs(1);
  AtmosphereModel double_hg;
  double_hg.mie_phase = MiePhaseModel::DoubleHenyeyGreenstein;
  double_hg.mie_g = 0.76f;
  for (const AtmosphereModel& model : {AtmosphereModel(), double_hg})
    for (double altitude : {2.0, 400e3})  // on the ground, and from space
    for (bool fixed : {false, true}) {
      AtmosphereSettings settings = small_settings();
      if (fixed) {
        settings.lut_precision = LutPrecision::Q15;
        settings.composite_precision = CompositePrecision::Fixed;
      }
      LutScheduler s(settings);
      s.set_model(model);
      const Camera cam = camera_at(altitude);
      const AtmospherePlan p = run_frame(s, 0, cam, sun_from_zenith(80.0), jobs);
      const SkyFrame f = frame_of(s, p, cam);
      // Directions all round (zenith and nadir included) and the sun's.
      std::vector<glm::vec3> dirs = {f.up, -f.up, f.sun, f.sun_horizontal};
      for (int a = 0; a < 24; ++a)
        for (int e = -12; e <= 12; ++e) {
          const float az = float(a) * 0.2618f, el = float(e) * 0.1309f;
          dirs.push_back(glm::normalize(glm::vec3(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az))));
        }
      for (int k = -400; k <= 40; ++k)  // fine steps across the horizon, and across the limb seen from space
        dirs.push_back(glm::normalize(glm::vec3(1.0f, float(k) * 1e-3f, 0.05f)));
      std::vector<float> dx, dy, dz;
      for (const glm::vec3& d : dirs) {
        dx.push_back(d.x);
        dy.push_back(d.y);
        dz.push_back(d.z);
      }
      std::vector<glm::vec3> batch(dirs.size());
      sky_radiance_batch(f, dirs.size(), dx.data(), dy.data(), dz.data(), batch.data());
      for (size_t i = 0; i < dirs.size(); ++i) {
        const glm::vec3 one = sky_radiance(f, dirs[i], false);
        CAPTURE(altitude);
        CAPTURE(i);
        CHECK(std::memcmp(&batch[i], &one, sizeof one) == 0);
      }
    }
}

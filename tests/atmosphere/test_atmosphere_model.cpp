// Model, phase functions, transmittance against closed forms, LUT mappings.
#include <doctest/doctest.h>

#include <array>
#include <cmath>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/atmosphere_settings.h"
#include "atmosphere/march_lookups.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/skyview_lut.h"
#include "atmosphere/transmittance_lut.h"
#include "engine/core/error.h"
#include "engine/core/math_constants.h"

using namespace cr;

namespace {

// 2 pi * integral of p(cos) over cos in [-1, 1] (Simpson, in double).
double sphere_integral(const std::function<double(double)>& p) {
  const int n = 200000;
  const double h = 2.0 / n;
  double s = p(-1.0) + p(1.0);
  for (int i = 1; i < n; ++i) s += p(-1.0 + i * h) * (i % 2 ? 4.0 : 2.0);
  return 2.0 * kPiD * s * h / 3.0;
}

AtmosphereModel homogeneous() {
  AtmosphereModel m;
  m.rayleigh_scale_height = 1e12f;  // density 1 everywhere in float
  m.mie_scattering = glm::vec3(0.0f);
  m.mie_absorption = glm::vec3(0.0f);
  m.ozone_absorption = glm::vec3(0.0f);
  return m;
}

AtmosphereModel exponential_rayleigh() {
  AtmosphereModel m;
  m.mie_scattering = glm::vec3(0.0f);
  m.mie_absorption = glm::vec3(0.0f);
  m.ozone_absorption = glm::vec3(0.0f);
  return m;
}

}  // namespace

TEST_CASE("phase functions integrate to one over the sphere") {
  CHECK(sphere_integral([](double c) { return rayleigh_phase(float(c)); }) == doctest::Approx(1.0).epsilon(1e-5));
  for (float g : {-0.9f, -0.5f, 0.0f, 0.3f, 0.76f, 0.8f, 0.9f}) {
    CAPTURE(g);
    CHECK(sphere_integral([g](double c) { return henyey_greenstein(float(c), g); }) ==
          doctest::Approx(1.0).epsilon(2e-4));
    CHECK(sphere_integral([g](double c) { return cornette_shanks(float(c), g); }) ==
          doctest::Approx(1.0).epsilon(2e-4));
  }
  AtmosphereModel m;
  m.mie_phase = MiePhaseModel::DoubleHenyeyGreenstein;
  m.mie_g = 0.76f;
  CHECK(sphere_integral([&](double c) { return mie_phase(m, float(c)); }) == doctest::Approx(1.0).epsilon(2e-4));
  // Forward peak: Mie scatters much more forwards than backwards.
  CHECK(mie_phase(m, 1.0f) > 50.0f * mie_phase(m, -1.0f));
}

TEST_CASE("the Mie phase's Legendre coefficients: g^l for Henyey-Greenstein") {
  AtmosphereModel m;
  m.mie_phase = MiePhaseModel::DoubleHenyeyGreenstein;
  m.mie_lobe_weight = 1.0f;  // one lobe: HG with g
  for (float g : {-0.7f, 0.0f, 0.3f, 0.8f, 0.95f}) {
    m.mie_g = g;
    const std::array<double, 2> k = mie_legendre_coefficients(m);
    CAPTURE(g);
    CHECK(k[0] == doctest::Approx(g).epsilon(1e-3).scale(1.0));
    CHECK(k[1] == doctest::Approx(double(g) * g).epsilon(1e-3).scale(1.0));
  }
}

TEST_CASE("the multiple-scattering view factors are the view direction in the sun-plane frame") {
  // A sample at radius r on the y axis, the sun in the x-y plane: v_y = v.up, v_x = v.(sun's horizontal).
  const float r = 6361e3f;
  for (float mu : {0.9f, 0.2f, -0.4f})        // the sun's zenith cosine at the sample
    for (float az : {0.0f, 1.0f, 2.5f})       // the view's azimuth from the sun
      for (float vy : {0.95f, 0.1f, -0.6f}) {  // the view's zenith cosine there
        const float sv = std::sqrt(1.0f - vy * vy), ss = std::sqrt(1.0f - mu * mu);
        const glm::vec3 v(sv * std::cos(az), vy, sv * std::sin(az)), sun(ss, mu, 0.0f);
        const float nu = glm::dot(v, sun);
        // The ray starts at t = 0 with r0 * its zenith cosine; at t = 0 the sample is the start.
        const MsView view = ms_view(r * vy, 0.0f, 1.0f / r, nu, mu);
        CAPTURE(mu);
        CAPTURE(az);
        CAPTURE(vy);
        CHECK(view.v_y == doctest::Approx(vy).epsilon(1e-5));
        CHECK(view.v_x == doctest::Approx(v.x).epsilon(1e-4).scale(1.0));
        CHECK(view.q_xx == doctest::Approx(v.x * v.x - v.z * v.z).epsilon(1e-4).scale(1.0));
        CHECK(view.q_yy == doctest::Approx(v.y * v.y - v.z * v.z).epsilon(1e-4).scale(1.0));
        CHECK(view.q_xy == doctest::Approx(2.0f * v.x * v.y).epsilon(1e-4).scale(1.0));
      }
}

TEST_CASE("transmittance through a homogeneous atmosphere matches exp(-sigma * length)") {
  const AtmosphereModel m = homogeneous();
  TransmittanceLut lut(m, 256, 64, 40);
  lut.bake(0, lut.texel_count());
  for (float h : {0.0f, 1000.0f, 20000.0f, 80000.0f}) {
    for (float mu : {1.0f, 0.5f, 0.1f, 0.0f}) {
      const double r = m.bottom_radius + h;
      const double len = distance_to_sphere_exit(r, mu, m.top_radius);
      const glm::vec3 expected = glm::exp(-m.rayleigh_scattering * float(len));
      const glm::vec3 direct = glm::exp(-optical_depth(m, h, mu, float(len), 40));
      const glm::vec3 looked_up = lut.to_top(lut.row(h), mu);
      CAPTURE(h);
      CAPTURE(mu);
      for (int c = 0; c < 3; ++c) {
        CHECK(direct[c] == doctest::Approx(expected[c]).epsilon(1e-4));
        CHECK(looked_up[c] == doctest::Approx(expected[c]).epsilon(0.02));
      }
    }
  }
}

TEST_CASE("transmittance through an exponential atmosphere matches the vertical closed form") {
  const AtmosphereModel m = exponential_rayleigh();
  TransmittanceLut lut(m, 256, 64, 40);
  lut.bake(0, lut.texel_count());
  const double H = m.rayleigh_scale_height;
  const double top = m.atmosphere_height();
  for (double h : {0.0, 2000.0, 10000.0, 50000.0}) {
    // Straight up: tau = sigma * H * (exp(-h/H) - exp(-top/H)).
    const double column = H * (std::exp(-h / H) - std::exp(-top / H));
    const glm::vec3 fine = optical_depth(m, float(h), 1.0f, float(top - h), 4000);
    const glm::vec3 looked_up = lut.to_top(lut.row(float(h)), 1.0f);
    CAPTURE(h);
    for (int c = 0; c < 3; ++c) {
      const double expected = std::exp(-double(m.rayleigh_scattering[c]) * column);
      CHECK(std::exp(-fine[c]) == doctest::Approx(expected).epsilon(1e-5));
      CHECK(looked_up[c] == doctest::Approx(expected).epsilon(5e-3));
    }
  }
  // And the reference's march (a different, adaptive integrator) agrees on a slant path.
  const glm::vec3 slant = glm::exp(-optical_depth(m, 0.0f, 0.3f, float(distance_to_sphere_exit(m.bottom_radius, 0.3, m.top_radius)), 4000));
  const glm::vec3 lut_slant = lut.to_top(lut.row(0.0f), 0.3f);
  for (int c = 0; c < 3; ++c) CHECK(lut_slant[c] == doctest::Approx(slant[c]).epsilon(5e-3));
}

TEST_CASE("rays from the ground: every downward one hits it at once, every upward one misses it") {
  const double R = AtmosphereModel{}.bottom_radius;
  int hits = 0;
  for (int i = 1; i < 1000; ++i) {
    const double mu = -double(i) / 1000.0;
    const double t = distance_to_ground(R, mu, R);
    hits += t == 0.0 ? 1 : 0;
    CHECK(distance_to_ground(R, -mu, R) == -1.0);
    // From 1 m above it: the near root in its cancellation-free form, (r^2 - R^2) / (-r mu + sqrt(disc)).
    const long double r = R + 1.0, c = (r - R) * (r + R), m = mu;
    const long double near = c / (-r * m + std::sqrt(r * r * m * m - c));
    CHECK(distance_to_ground(R + 1.0, mu, R) == doctest::Approx(double(near)).epsilon(1e-6));
  }
  CHECK(hits == 999);
}

TEST_CASE("the sun is shadowed by the planet with a smooth edge") {
  AtmosphereModel m;
  TransmittanceLut lut(m, 256, 64, 40);
  lut.bake(0, lut.texel_count());
  const float h = 10000.0f;
  const TransmittanceRow row = lut.row(h);
  CHECK(lut.sun(row, row.mu_horizon - 0.01f) == glm::vec3(0.0f));
  CHECK(lut.sun(row, row.mu_horizon + 0.01f).x > 0.0f);
  // Monotone across the penumbra.
  float prev = -1.0f;
  for (int i = 0; i <= 20; ++i) {
    const float mu = row.mu_horizon + row.penumbra * (float(i) / 10.0f - 1.0f);
    const float v = lut.sun(row, mu).x;
    CHECK(v >= prev);
    prev = v;
  }
}

TEST_CASE("LUT mappings round-trip") {
  AtmosphereModel m;
  const TransmittanceMapping tm(m);
  for (float x : {0.0f, 0.1f, 0.5f, 0.9f, 1.0f})
    for (float y : {0.0f, 0.05f, 0.5f, 0.95f, 1.0f}) {
      float h, mu;
      tm.from_unit({x, y}, h, mu);
      const glm::vec2 back = tm.to_unit(h, mu);
      CAPTURE(x);
      CAPTURE(y);
      CHECK(back.x == doctest::Approx(x).epsilon(2e-3));
      CHECK(back.y == doctest::Approx(y).epsilon(1e-3));
    }
  for (double altitude : {1.0, 1000.0, 50000.0, 400e3}) {
    const SkyViewMapping sm(m.bottom_radius, m.top_radius, altitude);
    for (float u : {0.0f, 0.2f, 0.7f, 1.0f})
      for (float v : {0.02f, 0.3f, 0.49f, 0.51f, 0.8f, 0.98f}) {
        double cz, cl;
        sm.from_unit({u, v}, cz, cl);
        const glm::vec2 back = sm.to_unit(float(cz), float(cl));
        CAPTURE(altitude);
        CAPTURE(u);
        CAPTURE(v);
        CHECK(back.x == doctest::Approx(u).epsilon(1e-3));
        CHECK(back.y == doctest::Approx(v).epsilon(1e-3));
      }
    // The horizon is exactly at v = 0.5, between the two middle rows.
    const double mu_h = horizon_mu(m.bottom_radius + altitude, m.bottom_radius);
    CHECK(sm.to_unit(float(mu_h) + 1e-4f, 1.0f).y < 0.5f);
    CHECK(sm.to_unit(float(mu_h) - 1e-4f, 1.0f).y > 0.5f);
  }
  using MsMapping = MultiScatteringMapping;
  for (float u : {0.0f, 0.03f, 2.0f / 31.0f, 0.2f, 0.5f, 20.0f / 31.0f, 0.8f, 1.0f}) {
    CAPTURE(u);
    CHECK(MsMapping::to_unit(MsMapping::from_unit(u)) == doctest::Approx(u).epsilon(1e-5));
  }
  CHECK(MsMapping::from_unit(0.0f) == -1.0f);
  CHECK(MsMapping::from_unit(1.0f) == doctest::Approx(1.0f));
  // Increasing and continuous where the pieces meet: no step larger than the dense piece's slope allows.
  const float dense_slope = (18.0f / 31.0f) / 0.4f, dmu = 0.005f;
  for (float mu = -1.0f; mu < 1.0f; mu += dmu) {
    const float du = MsMapping::to_unit(mu + dmu) - MsMapping::to_unit(mu);
    CAPTURE(mu);
    CHECK(du > 0.0f);
    CHECK(du <= dense_slope * dmu * 1.001f);
  }
}

TEST_CASE("bad atmosphere parameters are clear errors naming the field") {
  auto message = [](const nlohmann::json& j) {
    try {
      parse_atmosphere_scene(j, "scene.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message({{"preset", "earth-clear"}}).empty());
  CHECK(message({{"preset", "mars-like"}, {"ground_altitude_m", 100}}).empty());
  CHECK(message({{"preset", "venus"}}).find("atmosphere.preset") != std::string::npos);
  CHECK(message({{"mie_g", 1.0}}).find("atmosphere.mie_g") != std::string::npos);
  CHECK(message({{"mie_g", -1.5}}).find("|g|") != std::string::npos);
  CHECK(message({{"rayleigh_scattering", {1e-6, -1e-6, 1e-6}}}).find("atmosphere.rayleigh_scattering") !=
        std::string::npos);
  CHECK(message({{"atmosphere_height_m", -10}}).find("atmosphere.atmosphere_height_m") != std::string::npos);
  CHECK(message({{"colour", 1}}).find("atmosphere.colour: unknown key") != std::string::npos);
  CHECK(message({{"mie_phase", "rayleigh"}}).find("atmosphere.mie_phase") != std::string::npos);
  CHECK(message({{"ground_albedo", 1.5}}).find("atmosphere.ground_albedo") != std::string::npos);
  CHECK(message(nlohmann::json::array()).find("must be a JSON object") != std::string::npos);
  CHECK(parse_atmosphere_scene({{"preset", "earth-hazy"}}, "s").model.mie_scattering.x ==
        doctest::Approx(10.0f * AtmosphereModel().mie_scattering.x));
  CHECK(parse_atmosphere_scene({{"preset", "earth-dense"}}, "s").model.rayleigh_scattering.z ==
        doctest::Approx(10.0f * AtmosphereModel().rayleigh_scattering.z));
}

TEST_CASE("profile settings: defaults, overrides and errors") {
  const AtmosphereSettings d = parse_atmosphere_settings(nlohmann::json(), "p.json");
  CHECK(d.transmittance_width == 256);
  CHECK(d.schedule[size_t(LutKind::SkyView)].period == 4);
  CHECK(d.schedule[size_t(LutKind::AerialPerspective)].period == 6);
  const AtmosphereSettings s = parse_atmosphere_settings(
      {{"skyview_lut", {{"width", 96}, {"height", 54}}}, {"schedule", {{"full", true}, {"skyview", {{"period", 8}, {"slices", 4}}}}}},
      "p.json");
  CHECK(s.skyview_width == 96);
  CHECK(s.full_schedule);
  CHECK(s.schedule[size_t(LutKind::SkyView)].slices == 4);
  auto message = [](const nlohmann::json& j) {
    try {
      parse_atmosphere_settings(j, "p.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message({{"skyview_lut", {{"height", 55}}}}).find("atmosphere.skyview_lut.height") != std::string::npos);
  CHECK(message({{"schedule", {{"skyview", {{"period", 2}, {"slices", 4}}}}}}).find("atmosphere.schedule.skyview.slices") !=
        std::string::npos);
  CHECK(message({{"multiscattering_lut", {{"directions", 60}}}}).find("directions") != std::string::npos);
  CHECK(message({{"multiscattering_lut", {{"explicit_orders", 3}, {"max_explicit_orders", 2}}}})
            .find("atmosphere.multiscattering_lut.max_explicit_orders") != std::string::npos);
  CHECK(message({{"multiscattering_lut", {{"tail_share", 0}}}}).find("atmosphere.multiscattering_lut.tail_share") !=
        std::string::npos);
  // A minimum above the default maximum raises the maximum with it.
  CHECK(parse_atmosphere_settings({{"multiscattering_lut", {{"explicit_orders", 6}}}}, "p.json")
            .multiscattering_max_explicit_orders == 6);
  CHECK(message({{"transmittance_lut", {{"size", 3}}}}).find("atmosphere.transmittance_lut.size: unknown key") !=
        std::string::npos);
  CHECK(message({{"space_fallback_altitude_m", "high"}}).find("atmosphere.space_fallback_altitude_m") !=
        std::string::npos);
}

// The split-sum specular ambient: the DFG table, the prefiltered octahedral
// environment (prefilter, sampling, seams, determinism), specular occlusion,
// and the furnace test through shade_surface.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "brdf_quadrature.h"
#include "engine/core/fast_math.h"
#include "engine/core/math_constants.h"
#include "engine/shading/brdf.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/environment_prefilter.h"
#include "engine/shading/ggx_sampling.h"
#include "engine/shading/shade_surface.h"
#include "engine/shading/sh_lighting.h"
#include "engine/shading/specular_occlusion.h"

using namespace cr;
using namespace cr::test;

namespace {

// A radiance function with no symmetry about the octahedral folds, a bright
// lobe (a sun-lit haze) and a smooth gradient: seams and lobes both show.
glm::vec3 test_radiance(const glm::vec3& d) {
  const glm::vec3 s = glm::normalize(glm::vec3(0.5f, 0.4f, -0.3f));
  const float lobe = 6.0f * std::exp(-8.0f * (1.0f - glm::dot(d, s)));
  return glm::vec3(2.0f + d.x + 0.5f * d.z + 0.3f * d.x * d.z, 1.5f + 0.7f * d.y, 1.0f + 0.4f * d.x * d.y) + lobe;
}

EnvironmentPrefilter::Radiance radiance_of(glm::vec3 (*f)(const glm::vec3&)) {
  return [f](size_t n, const float* x, const float* y, const float* z, glm::vec3* out) {
    for (size_t i = 0; i < n; ++i) out[i] = f(glm::vec3(x[i], y[i], z[i]));
  };
}

glm::vec3 white(const glm::vec3&) { return glm::vec3(1.0f); }

float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// Karis' prefilter integral with n = v = R, brute force over the source
// (level 0, bilinear) on a fine (theta, phi) grid around R:
// int L(l) D(h) (R.l) dl / int D(h) (R.l) dl.
glm::vec3 brute_force_prefilter(const SpecularEnvironment& env, const glm::vec3& r, float roughness) {
  const float alpha = std::max(roughness * roughness, kMinRoughness * kMinRoughness);
  glm::vec3 t, b;
  orthonormal_frame(r, t, b);
  constexpr int kTheta = 768, kPhi = 384;
  glm::dvec3 sum(0.0);
  double weight = 0.0;
  for (int i = 0; i < kTheta; ++i) {
    const float theta = (float(i) + 0.5f) / kTheta * 0.5f * kPi;
    for (int j = 0; j < kPhi; ++j) {
      const float phi = (float(j) + 0.5f) / kPhi * 2.0f * kPi;
      const glm::vec3 local(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const glm::vec3 h = glm::normalize(local + glm::vec3(0, 0, 1));
      const double w = double(ggx_distribution(h.z, alpha)) * local.z * std::sin(theta);
      sum += w * glm::dvec3(env.sample_level(local.x * t + local.y * b + local.z * r, 0.0f));
      weight += w;
    }
  }
  return glm::vec3(sum / weight);
}

Material material(float base, float metallic, float roughness) {
  Material m;
  m.base_color_factor = glm::vec4(base, base, base, 1.0f);
  m.metallic_factor = metallic;
  m.roughness_factor = roughness;
  return m;
}

SurfaceSample flat_env_sample() {
  SurfaceSample s;
  s.normal = {0, 1, 0};
  s.tangent = {1, 0, 0, 1};
  return s;
}

}  // namespace

TEST_CASE("DFG table: matches an independent quadrature of the BRDF and its known limits") {
  const DfgTable& t = DfgTable::get();
  constexpr int n = DfgTable::kSize;
  // A + B is the white metal's albedo (f0 = 1), B the albedo with f0 = 0:
  // directional_albedo integrates evaluate_brdf by its own quadrature
  // (error below 2e-3, see test_brdf.cpp). At the nodes the table is the
  // importance-sampled integral (1024 Hammersley points): measured worst
  // 6.1e-3, at n.v = 0.16 (grazing views converge slowest).
  double worst = 0.0;
  for (int j : {8, 16, 24, 31})
    for (int i : {31, 22, 12, 5}) {
      const float r = float(j) / float(n - 1), nv = float(i) / float(n - 1);
      CAPTURE(r);
      CAPTURE(nv);
      const EnvironmentBrdf e = t.node(i, j);
      const float ab = directional_albedo({glm::vec3(1.0f), 1.0f, r}, nv);
      const float b = directional_albedo({glm::vec3(0.0f), 1.0f, r}, nv);
      CHECK(std::abs(e.a + e.b - ab) < 8e-3f);
      CHECK(std::abs(e.b - b) < 8e-3f);
      worst = std::max({worst, double(std::abs(e.a + e.b - ab)), double(std::abs(e.b - b))});
      // The lookup reads the node exactly there.
      const EnvironmentBrdf l = t.lookup(r, nv);
      CHECK(std::abs(l.a - e.a) < 1e-6f);
      CHECK(std::abs(l.b - e.b) < 1e-6f);
    }
  MESSAGE("DFG table vs quadrature: worst abs error " << worst);
  // Between nodes: bilinear, within 1e-2 of the integral itself.
  for (float r : {0.13f, 0.37f, 0.61f, 0.88f})
    for (float nv : {0.05f, 0.33f, 0.58f, 0.93f}) {
      const EnvironmentBrdf l = environment_brdf(r, nv), e = integrate_environment_brdf(r, nv, 4096);
      CHECK(std::abs(l.a - e.a) < 1e-2f);
      CHECK(std::abs(l.b - e.b) < 1e-2f);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const EnvironmentBrdf e = t.node(i, j);
      // Energy: single-scattering GGX never reflects more than it receives.
      CHECK(e.a >= 0.0f);
      CHECK(e.b >= 0.0f);
      CHECK(e.a + e.b <= 1.0f + 1e-3f);
      // Rougher loses more (the multiple-scattering share it lacks).
      CAPTURE(i);
      CAPTURE(j);
      // (From n.v ~ 0.19 up: at grazing, masking makes the albedo dip and rise again.)
      if (j > 0 && i >= 6) CHECK(e.a + e.b <= t.node(i, j - 1).a + t.node(i, j - 1).b + 1e-3f);
    }
  // Smooth limit (roughness -> kMinRoughness): a mirror with Schlick's F at
  // v.h = n.v: A = 1 - (1 - n.v)^5, B = (1 - n.v)^5.
  for (int i = 3; i < n; i += 4) {
    const float nv = float(i) / float(n - 1);
    const float w = fresnel_weight(nv);
    CHECK(std::abs(t.node(i, 0).a - (1.0f - w)) < 1e-2f);
    CHECK(std::abs(t.node(i, 0).b - w) < 1e-2f);
  }
  // Normal view, roughness 1: the white metal keeps 1 - ln 2 (test_brdf.cpp).
  CHECK(t.node(n - 1, n - 1).a + t.node(n - 1, n - 1).b == doctest::Approx(1.0f - std::log(2.0f)).epsilon(1e-2));
}

TEST_CASE("specular occlusion: 1 without occlusion, 0 at full occlusion, ~ao for rough lobes") {
  for (float nv : {0.001f, 0.2f, 0.7f, 1.0f})
    for (float alpha : {0.002f, 0.1f, 0.5f, 1.0f}) {
      CHECK(specular_occlusion(nv, 1.0f, alpha) == 1.0f);
      CHECK(specular_occlusion(nv, 0.0f, alpha) == 0.0f);
    }
  // Lagarde's fit at one point, against std::pow.
  const float nv = 0.6f, ao = 0.4f, alpha = 0.09f;
  const float expected = std::pow(nv + ao, std::exp2(-16.0f * alpha - 1.0f)) - 1.0f + ao;
  CHECK(specular_occlusion(nv, ao, alpha) == doctest::Approx(expected).epsilon(1e-5));
  CHECK(specular_occlusion(1.0f, 0.5f, 1.0f) == doctest::Approx(0.5f).epsilon(1e-3));  // rough: ao
  CHECK(specular_occlusion(1.0f, 0.5f, 0.002f) > 0.7f);  // smooth, facing: sees past the occluder
  for (float x : {1e-30f, 1e-3f, 0.37f, 1.0f, 1.5f, 1.999f, 2.0f, 77.0f})
    CHECK(fast_log2(x) == doctest::Approx(std::log2(x)).epsilon(0.0).scale(1.0f).epsilon(1e-6));
  CHECK(fast_log2(1.0f) == 0.0f);
}

TEST_CASE("specular environment: octahedral mapping round trip and seam continuity at every level") {
  for (int k = 0; k < 200; ++k) {
    const float a = float(k) * 2.3999632f, y = 1.0f - 2.0f * (float(k) + 0.5f) / 200.0f;
    const glm::vec3 d(std::sqrt(1.0f - y * y) * std::cos(a), y, std::sqrt(1.0f - y * y) * std::sin(a));
    const glm::vec3 back = octahedral_decode(octahedral_encode(d));
    CHECK(glm::length(back - d) < 1e-5f);
  }
  JobSystem jobs(2);
  const auto env = prefilter_environment(16, 4, 32, radiance_of(test_radiance), jobs);
  // Pairs of directions a hair apart on either side of a seam (the lower
  // half of the planes x = 0 and z = 0: the square's edges) and around the
  // nadir (its corners) read the same radiance; a wrong border would read a
  // texel on the far side of the map. The gradient check: steps along a
  // path crossing the seams change no more than steps elsewhere.
  const float eps = 1e-5f;
  for (int level = 0; level < env->levels(); ++level) {
    CAPTURE(level);
    for (float t : {-0.9f, -0.6f, -0.3f, 0.3f, 0.6f, 0.9f})
      for (float down : {0.05f, 0.4f, 0.8f, 1.5f}) {
        const glm::vec3 across_x0 = env->sample_level(glm::vec3(eps, -down, t), float(level));
        const glm::vec3 across_x1 = env->sample_level(glm::vec3(-eps, -down, t), float(level));
        const glm::vec3 across_z0 = env->sample_level(glm::vec3(t, -down, eps), float(level));
        const glm::vec3 across_z1 = env->sample_level(glm::vec3(t, -down, -eps), float(level));
        CHECK(max_component(glm::abs(across_x0 - across_x1)) < 1e-3f * max_component(across_x0));
        CHECK(max_component(glm::abs(across_z0 - across_z1)) < 1e-3f * max_component(across_z0));
      }
    const glm::vec3 nadir = env->sample_level(glm::vec3(0, -1, 0), float(level));
    for (int a = 0; a < 8; ++a) {
      const float phi = float(a) * 0.25f * kPi + 0.1f;
      const glm::vec3 near = env->sample_level(glm::vec3(eps * std::cos(phi), -1.0f, eps * std::sin(phi)), float(level));
      CHECK(max_component(glm::abs(near - nadir)) < 1e-3f * max_component(nadir));
    }
    // A great circle through the nadir crossing both seams, in 720 steps.
    float worst_step = 0.0f;
    glm::vec3 prev = env->sample_level(glm::vec3(1, 0, 0.3f), float(level));
    for (int s = 1; s <= 720; ++s) {
      const float a = float(s) / 720.0f * 2.0f * kPi;
      const glm::vec3 cur = env->sample_level(glm::vec3(std::cos(a), -std::sin(a), 0.3f), float(level));
      worst_step = std::max(worst_step, max_component(glm::abs(cur - prev)));
      prev = cur;
    }
    // The function changes by at most ~|grad| * step; texel interpolation at 16x16 adds a kink, not a jump.
    CHECK(worst_step < 0.25f);
  }
}

TEST_CASE("specular environment: a white furnace keeps radiance 1 at every level; shading gives the DFG albedo") {
  JobSystem jobs(2);
  const auto env = prefilter_environment(16, 5, 32, radiance_of(white), jobs);
  for (int k = 0; k < env->levels(); ++k)
    for (int y = 0; y < env->size(k); ++y)
      for (int x = 0; x < env->size(k); ++x) CHECK(max_component(glm::abs(env->texel(k, x, y) - 1.0f)) < 1e-5f);

  Scene scene;
  LightEnvironment light;  // no sun
  light.sun_illuminance = glm::vec3(0.0f);
  light.ambient_sh = sh_constant_radiance(glm::vec3(1.0f));
  light.specular = env;
  for (float elevation : {90.0f, 60.0f, 30.0f, 10.0f}) {
    const float e = glm::radians(elevation);
    const ShadingInputs in{&scene, &light, nullptr, glm::dvec3(std::cos(e), std::sin(e), 0.0) * 5.0};
    const float nv = std::sin(e);
    CAPTURE(elevation);
    for (float r : {0.3f, 0.6f, 1.0f}) {
      CAPTURE(r);
      // White metal: A + B of the table (radiance 1 in, f0 = 1); the
      // independent quadrature of the BRDF within the table's error plus
      // its bilinear interpolation (8e-3).
      const EnvironmentBrdf dfg = environment_brdf(r, nv);
      const glm::vec4 metal = shade_surface(in, material(1.0f, 1.0f, r), flat_env_sample());
      CHECK(metal.r == doctest::Approx(dfg.a + dfg.b).epsilon(1e-5));
      CHECK(std::abs(metal.r - directional_albedo({glm::vec3(1.0f), 1.0f, r}, nv)) < 8e-3f);
      // White dielectric: the split keeps what the specular lobe takes from
      // the diffuse one, so exactly the incoming radiance. The glTF BRDF's
      // own albedo (fresnel_mix per light direction) is within 5% of it
      // at roughness >= 0.6 and n.v >= 0.17 (measured 4.6% at 0.6 / 0.17:
      // its rough lobe loses a little, its diffuse weight 1 - F(v.h) gains
      // a little towards grazing).
      const glm::vec4 dielectric = shade_surface(in, material(1.0f, 0.0f, r), flat_env_sample());
      CHECK(dielectric.r == doctest::Approx(1.0f).epsilon(1e-5));
      if (r >= 0.6f)
        CHECK(std::abs(dielectric.r - directional_albedo({glm::vec3(1.0f), 0.0f, r}, nv)) < 5e-2f);
    }
  }
}

TEST_CASE("specular environment: prefiltered levels match a brute-force convolution of the source") {
  JobSystem jobs(2);
  const auto env = prefilter_environment(32, 5, 64, radiance_of(test_radiance), jobs);
  for (int k = 1; k < env->levels(); ++k) {
    const int n = env->size(k);
    double sum = 0.0, worst = 0.0;
    int count = 0;
    for (int y = 1; y < n; y += std::max(1, n / 5))
      for (int x = 0; x < n; x += std::max(1, n / 5)) {
        const glm::vec3 r = SpecularEnvironment::texel_direction(n, x, y);
        const glm::vec3 ref = brute_force_prefilter(*env, r, env->roughness(k));
        const glm::vec3 got = env->texel(k, x, y);
        const double e = max_component(glm::abs(got - ref) / ref);
        sum += e;
        worst = std::max(worst, e);
        ++count;
      }
    MESSAGE("level " << k << " (roughness " << env->roughness(k) << ", " << n << "x" << n << "): mean rel error "
                     << sum / count << ", max " << worst);
    // Measured (64 samples at level 0's size): mean 0.3-0.9%, max 0.9-2.2%.
    CHECK(sum / count < 0.015);
    CHECK(worst < 0.035);
  }
}

TEST_CASE("specular environment: bit-identical for 1 and 3 threads and for any split into slices; batch = scalar") {
  JobSystem one(1), three(3);
  const auto a = prefilter_environment(16, 4, 16, radiance_of(test_radiance), one);
  EnvironmentPrefilter sliced(16, 4, 16);
  const size_t items = sliced.work_items();
  size_t done = 0;
  for (size_t step : {size_t(5), size_t(13), size_t(1), size_t(200), items}) {
    const size_t end = std::min(items, done + step);
    sliced.run(done, end, radiance_of(test_radiance), three, "test");
    done = end;
  }
  REQUIRE(sliced.complete());
  const auto& b = *sliced.result();
  CHECK_THROWS(sliced.run(0, 1, radiance_of(test_radiance), three, "test"));  // out of order
  size_t differing = 0;
  for (int k = 0; k < a->levels(); ++k)
    for (int y = 0; y < a->size(k); ++y)
      for (int x = 0; x < a->size(k); ++x) differing += a->texel(k, x, y) != b.texel(k, x, y) ? 1 : 0;
  CHECK(differing == 0);

  constexpr size_t kN = 97;
  float dx[kN], dy[kN], dz[kN], rough[kN], r[kN], g[kN], bl[kN];
  for (size_t i = 0; i < kN; ++i) {
    dx[i] = std::cos(float(i) * 1.7f);
    dy[i] = std::sin(float(i) * 0.9f);
    dz[i] = std::sin(float(i) * 2.3f) * 0.5f;
    rough[i] = float(i % 11) / 10.0f;
  }
  // Out of range, NaN and zero inputs too: clamped the same way on both paths.
  rough[3] = -0.5f;
  rough[4] = 1.5f;
  rough[5] = std::nanf("");
  dx[6] = dy[6] = dz[6] = 0.0f;
  dx[7] = dz[7] = 0.0f;
  dy[7] = -1.0f;
  a->sample_batch(kN, dx, dy, dz, rough, r, g, bl);
  for (size_t i = 0; i < kN; ++i) {
    CAPTURE(i);
    const glm::vec3 d(dx[i], dy[i], dz[i]);
    CHECK(a->sample(d, rough[i]) == glm::vec3(r[i], g[i], bl[i]));
    // The batch's vectorised steps and sample_level's scalar ones: the same floats.
    CHECK(a->sample_level(d, rough[i] * float(a->levels() - 1)) == glm::vec3(r[i], g[i], bl[i]));
  }
}

TEST_CASE("specular environment in q15: texels on the grid, batch = scalar bit for bit, within 2 codes of float") {
  JobSystem jobs(1);
  const auto built = prefilter_environment(16, 4, 16, radiance_of(test_radiance), jobs);
  const SpecularEnvironment& f = *built;
  SpecularEnvironment q = f;
  q.quantize_q15();
  REQUIRE(q.quantized());
  float peak = 0.0f;
  for (int k = 0; k < f.levels(); ++k)
    for (int y = 0; y < f.size(k); ++y)
      for (int x = 0; x < f.size(k); ++x) {
        const glm::vec3 a = f.texel(k, x, y), b = q.texel(k, x, y);
        for (int c = 0; c < 3; ++c) {
          peak = std::max(peak, a[c]);
          CHECK(std::abs(a[c] - b[c]) <= 0.5f * q.code_scale() / 32768.0f + 2.4e-7f * a[c]);
        }
      }
  CHECK(q.code_scale() == doctest::Approx(peak * 32768.0f / 32767.0f));
  constexpr size_t kN = 301;
  std::vector<float> dx(kN), dy(kN), dz(kN), rough(kN), r(kN), g(kN), b(kN);
  for (size_t i = 0; i < kN; ++i) {
    dx[i] = std::cos(float(i) * 1.7f);
    dy[i] = std::sin(float(i) * 0.9f);
    dz[i] = std::sin(float(i) * 2.3f) * 0.5f;
    rough[i] = float(i % 23) / 22.0f;
  }
  rough[3] = std::nanf("");
  q.sample_batch(kN, dx.data(), dy.data(), dz.data(), rough.data(), r.data(), g.data(), b.data());
  for (size_t i = 0; i < kN; ++i) {
    CAPTURE(i);
    const glm::vec3 d(dx[i], dy[i], dz[i]);
    CHECK(q.sample(d, rough[i]) == glm::vec3(r[i], g[i], b[i]));
    CHECK(q.sample_level(d, rough[i] * float(q.levels() - 1)) == glm::vec3(r[i], g[i], b[i]));
    // Three rounded lerps on the rounded texels against float lerps of them: within 2 codes.
    const glm::vec3 exact = f.sample(d, rough[i]);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(glm::vec3(r[i], g[i], b[i])[c] - exact[c]) <= 2.0f * q.code_scale() / 32768.0f);
  }
}

TEST_CASE("DFG table: lookup_batch = lookup bit for bit, across chunks and at the edges") {
  const DfgTable& t = DfgTable::get();
  constexpr size_t kN = 150;  // more than one of lookup_batch's chunks
  float rough[kN], nv[kN], a[kN], b[kN];
  for (size_t i = 0; i < kN; ++i) {
    rough[i] = std::fmod(float(i) * 0.137f, 1.1f) - 0.05f;
    nv[i] = std::fmod(float(i) * 0.291f, 1.2f) - 0.1f;
  }
  rough[0] = nv[1] = 1.0f;
  rough[2] = nv[2] = 0.0f;
  rough[3] = std::nanf("");
  nv[4] = std::nanf("");
  t.lookup_batch(kN, rough, nv, a, b);
  for (size_t i = 0; i < kN; ++i) {
    CAPTURE(i);
    const EnvironmentBrdf e = t.lookup(rough[i], nv[i]);
    CHECK(e.a == a[i]);
    CHECK(e.b == b[i]);
  }
}

TEST_CASE("shade: with an environment, a smooth metal reflects it and SurfaceShader batches match shade_surface") {
  JobSystem jobs(2);
  Scene scene;
  LightEnvironment light;
  light.sun_direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));
  light.sun_illuminance = glm::vec3(5e4f);
  light.ambient_sh = sh_constant_radiance(glm::vec3(500.0f));
  light.specular = prefilter_environment(32, 6, 32, radiance_of(test_radiance), jobs);
  const glm::dvec3 camera(2.0, 3.0, 1.0);
  const ShadingInputs in{&scene, &light, nullptr, camera};
  // Smooth white metal facing the camera along the normal: the mirror
  // direction is the view direction itself; it reflects L(R) * (A + B).
  SurfaceSample s = flat_env_sample();
  s.normal = glm::normalize(glm::vec3(camera));
  const glm::vec3 r = s.normal;
  light.sun_illuminance = glm::vec3(0.0f);
  const glm::vec4 mirror = shade_surface(in, material(1.0f, 1.0f, 0.0f), s);
  const EnvironmentBrdf e = environment_brdf(kMinRoughness, 1.0f);
  const glm::vec3 expected = light.specular->sample(r * (1.0f - kMinRoughness * kMinRoughness) +
                                                        r * (kMinRoughness * kMinRoughness),
                                                    kMinRoughness) *
                             (e.a + e.b);
  for (int c = 0; c < 3; ++c) CHECK(mirror[c] == doctest::Approx(expected[c]).epsilon(1e-5));
  CHECK(glm::length(glm::vec3(mirror) / (e.a + e.b) - test_radiance(r)) < 0.05f * glm::length(test_radiance(r)));

  light.sun_illuminance = glm::vec3(5e4f);
  SurfaceShader shader(in);
  ShadingBatch batch;
  std::vector<glm::vec4> single;
  for (int i = 0; i < 40; ++i) {
    SurfaceSample p = flat_env_sample();
    p.position = glm::vec3(float(i) * 0.1f, 0.0f, float(i % 7) * 0.2f);
    p.normal = glm::normalize(glm::vec3(std::sin(float(i)), 1.0f, std::cos(float(i) * 0.7f)));
    const Material m = material(0.2f + 0.02f * float(i), float(i % 3) * 0.5f, float(i % 5) * 0.25f);
    single.push_back(shade_surface(in, m, p));
    shader.add(batch, m, p);
  }
  shader.shade_batch(batch);
  for (int i = 0; i < 40; ++i) CHECK(glm::vec4(batch.radiance(i), batch.alpha[i]) == single[size_t(i)]);
}

// The LUT bakes' fast paths (sky-view rows shaded in one batch, aerial
// perspective columns marched whole, rgb + pad texel copies) give exactly the
// results of the straightforward per-direction, per-slice formulas.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "atmosphere/aerial_perspective_lut.h"
#include "atmosphere/froxel_column.h"
#include "atmosphere/march_lookups.h"
#include "atmosphere/phase_functions.h"
#include "atmosphere/planet_geometry.h"
#include "atmosphere/scattering_march.h"
#include "atmosphere_test_util.h"
#include "engine/core/math_constants.h"

using namespace cr;
using namespace cr::test;

namespace {

bool same_bits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const float* packed, const glm::vec3& v) { return std::memcmp(packed, &v, sizeof v) == 0; }

// shade_split written the plain way: one direction, LUT lookups through
// TransmittanceLut::sun and sample_bilinear.
ShadedRay shade_reference(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu) {
  const float phase_r = rayleigh_phase(nu);
  const MultiScatteringLut& msl = luts.multiscattering;
  const LutImage& ms = msl.image();
  const float r0_mu_s = ray.r0 * mu_s;
  const float mie_ratio = msl.mie_quadratic_ratio();
  glm::vec3 l(0.0f), mie(0.0f);
  for (const MarchSample& s : ray.samples) {
    const float mu_s_t = std::clamp((r0_mu_s + s.t * nu) * s.inv_r, -1.0f, 1.0f);
    const glm::vec3 sun = luts.transmittance.sun(s.row, mu_s_t);
    const float x = MultiScatteringMapping::to_unit(mu_s_t) * float(ms.width - 1);
    auto at = [&](const LutImage& image) { return sample_bilinear(image, x, s.ms_y); };
    const glm::vec3 psi = at(ms);
    const MsView v = ms_view(ray.r0_mu, s.t, s.inv_r, nu, mu_s_t);
    const glm::vec3 quadratic = at(msl.moment_image(kMsQuadXX)) * v.q_xx + at(msl.moment_image(kMsQuadYY)) * v.q_yy +
                                at(msl.moment_image(kMsQuadXY)) * v.q_xy;
    const glm::vec3 first = at(msl.moment_image(kMsFirstX)) * v.v_x + at(msl.moment_image(kMsFirstY)) * v.v_y;
    const glm::vec3 multiple = psi * s.w_ms + quadratic * s.w_rayleigh + (quadratic * mie_ratio + first) * s.w_mie;
    l += sun * s.w_rayleigh * phase_r + glm::max(multiple, glm::vec3(0.0f));
    mie += sun * s.w_mie;
  }
  if (ray.hits_ground) {
    const float inv_r = 1.0f / float(luts.model.bottom_radius);
    const float mu_g = std::clamp((r0_mu_s + ray.ground_t * nu) * inv_r, -1.0f, 1.0f);
    const glm::vec3 sun = luts.transmittance.sun(ray.ground_row, mu_g) * std::max(mu_g, 0.0f);
    const glm::vec3 psi = sample_bilinear(ms, MultiScatteringMapping::to_unit(mu_g) * float(ms.width - 1), 0.0f);
    l += ray.transmittance * luts.model.ground_albedo * (sun / kPi + psi);
  }
  return {l, mie};
}

struct Luts {
  JobSystem jobs{1};
  LutScheduler scheduler{small_settings()};
  explicit Luts(double sun_zenith_deg) {
    run_frame(scheduler, 0, camera_at(2.0), sun_from_zenith(sun_zenith_deg), jobs);
  }
  AtmosphereLuts get() const {
    return {scheduler.model(), *scheduler.multiscattering_source(), *scheduler.multiscattering()};
  }
};

}  // namespace

TEST_CASE("a sky-view row shaded in one batch equals shading each direction alone, bit for bit") {
  for (double zenith : {30.0, 89.0, 93.0}) {  // day, sunset (the shadow's penumbra), sun below the horizon
    const Luts l(zenith);
    const AtmosphereLuts luts = l.get();
    const float mu_s = float(std::cos(zenith * kPiD / 180.0));
    // Longitudes around the sun, an odd count (the vector loop's remainder too).
    std::vector<float> nu;
    for (int j = 0; j < 37; ++j) nu.push_back(std::clamp(std::cos(float(j) * 0.0873f) * 0.999f, -1.0f, 1.0f));
    nu.push_back(1.0f);
    nu.push_back(-1.0f);
    MarchedRay ray;
    for (float mu : {0.7f, 0.02f, -0.3f}) {  // up, grazing, into the ground
      const double r = luts.model.bottom_radius + 2.0;
      const double t_ground = distance_to_ground(r, mu, luts.model.bottom_radius);
      const bool ground = t_ground >= 0.0;
      const double t_end = ground ? t_ground : distance_to_sphere_exit(r, mu, luts.model.top_radius);
      march(luts, 2.0f, mu, 0.0f, float(t_end), 11, StepSpacing::Quadratic, ground, 0.0f, ray);
      std::vector<ShadedRay> batch(nu.size());
      shade_split_many(luts, ray, mu_s, nu.size(), nu.data(), batch.data());
      for (size_t j = 0; j < nu.size(); ++j) {
        CAPTURE(zenith);
        CAPTURE(mu);
        CAPTURE(nu[j]);
        const ShadedRay ref = shade_reference(luts, ray, mu_s, nu[j]);
        const ShadedRay one = shade_split(luts, ray, mu_s, nu[j]);
        CHECK(same_bits(batch[j].rest, ref.rest));
        CHECK(same_bits(batch[j].mie_unphased, ref.mie_unphased));
        CHECK(same_bits(one.rest, ref.rest));
        CHECK(same_bits(one.mie_unphased, ref.mie_unphased));
      }
    }
  }
}

TEST_CASE("a column's runs shaded at once equal accumulating and shading each run alone, bit for bit") {
  for (double zenith : {30.0, 89.0, 93.0}) {  // day, the shadow's penumbra, sun below the horizon
    const Luts l(zenith);
    const AtmosphereLuts luts = l.get();
    const float mu_s = float(std::cos(zenith * kPiD / 180.0));
    const size_t run = 3, runs = 7;  // an odd step count: the vector loop's remainder too
    MarchSteps steps;
    steps.resize(run * runs);
    for (size_t k = 0; k < run * runs; ++k) {
      steps.dt[k] = 150.0f * float(k + 1);
      steps.t[k] = 75.0f * float((k + 1) * (k + 1));
    }
    for (float mu : {0.6f, 0.01f, -0.2f}) {  // up, grazing, down (samples pushed up to the floor)
      for (float nu : {1.0f, 0.3f, -0.9f}) {
        const float h0 = 5.0f;
        march_media(luts.model, h0, mu, 5.0f, steps);
        std::vector<ShadedRay> shaded(runs);
        std::vector<glm::vec3> transmittance(runs);
        shade_runs(luts, steps, h0, mu, mu_s, nu, run, shaded.data(), transmittance.data());
        MarchedRay ray;
        for (size_t r = 0; r < runs; ++r) {
          accumulate(luts, steps, r * run, (r + 1) * run, h0, mu, ray);
          const ShadedRay ref = shade_split(luts, ray, mu_s, nu);
          CAPTURE(zenith);
          CAPTURE(mu);
          CAPTURE(nu);
          CAPTURE(r);
          CHECK(same_bits(shaded[r].rest, ref.rest));
          CHECK(same_bits(shaded[r].mie_unphased, ref.mie_unphased));
          CHECK(same_bits(transmittance[r], ray.transmittance));
        }
      }
    }
  }
}

TEST_CASE("an aerial-perspective column marched at once equals marching it slice by slice, bit for bit") {
  const Luts l(60.0);
  const AtmosphereLuts luts = l.get();
  // A camera 5 m up looking slightly down: some froxels under the ground are pushed up.
  const Camera cam = camera_at(5.0, 0.0, 20.0);
  AtmosphereFrameInputs in = frame_inputs(luts.model, planet_offset(scene_config(luts.model)), 0, cam,
                                          sun_from_zenith(60.0));
  const int w = 8, h = 8, depth = 8, steps = 2;
  AerialPerspectiveLut ap(w, h, depth, 4.0f, steps, in.camera);
  ap.bake(0, ap.column_count(), luts);
  const FroxelCamera& c = ap.camera();
  const double r0 = glm::length(c.position);
  const glm::dvec3 up = c.position / r0;
  const float h0 = float(r0 - luts.model.bottom_radius);
  const float mu_s = float(glm::dot(glm::dvec3(c.sun_direction), up));
  MarchedRay ray;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 dir = c.column_direction(float(x) + 0.5f, float(y) + 0.5f, w, h);
      const float mu = float(glm::dot(glm::dvec3(dir), up));
      const float nu = std::clamp(glm::dot(dir, c.sun_direction), -1.0f, 1.0f);
      glm::vec3 lum(0.0f), tr(1.0f);
      float t_begin = 0.0f;
      for (int s = 0; s < depth; ++s) {
        const float t_end = ap.slice_distance(s);
        march(luts, std::max(h0, 0.0f), mu, t_begin, t_end, steps, StepSpacing::Uniform, false,
              std::clamp(h0, 0.0f, 10.0f), ray);
        lum += tr * shade(luts, ray, mu_s, nu);
        tr *= ray.transmittance;
        t_begin = t_end;
        CAPTURE(x);
        CAPTURE(y);
        CAPTURE(s);
        CHECK(same_bits(ap.luminance().at(x, y, s), lum));
        CHECK(same_bits(ap.transmittance().at(x, y, s), tr));
      }
    }
}

TEST_CASE("packed texel copies equal the LUT images, the froxel padding repeats the last column and row") {
  const Luts l(45.0);
  const AtmosphereLuts luts = l.get();
  const LutImage& t = luts.transmittance.image();
  for (size_t i = 0; i < t.count(); ++i) REQUIRE(same_bits(luts.transmittance.packed() + 4 * i, t.texels[i]));
  const LutImage& ms = luts.multiscattering.image();
  for (size_t i = 0; i < ms.count(); ++i) REQUIRE(same_bits(luts.multiscattering.packed() + 4 * i, ms.texels[i]));

  const AerialPerspectiveLut& ap = *l.scheduler.aerial_perspective();
  const int w = ap.luminance().width, h = ap.luminance().height, d = ap.luminance().depth;
  REQUIRE(ap.packed().size() == size_t(w + 1) * size_t(h + 1) * size_t(d));
  for (int z = 0; z < d; ++z)
    for (int y = 0; y <= h; ++y)
      for (int x = 0; x <= w; ++x) {
        const FroxelTexel& p = ap.packed()[ap.packed_index(x, y, z)];
        const int sx = std::min(x, w - 1), sy = std::min(y, h - 1);
        REQUIRE(same_bits(p.luminance, ap.luminance().at(sx, sy, z)));
        REQUIRE(same_bits(p.transmittance, ap.transmittance().at(sx, sy, z)));
      }
}

TEST_CASE("batched sun transmittance lookups equal TransmittanceLut::sun, bit for bit") {
  const Luts l(45.0);
  const TransmittanceLut& t = *l.scheduler.multiscattering_source();
  // Altitudes under the ground, on it, across the atmosphere and above its top; sun
  // cosines past both ends, through the shadow's penumbra at each altitude's horizon.
  std::vector<float> altitude, mu_s;
  for (float h : {-50.0f, 0.0f, 1.5f, 320.0f, 4000.0f, 25000.0f, 99999.0f, 1.2e5f})
    for (int j = 0; j <= 40; ++j) {
      altitude.push_back(h);
      mu_s.push_back(-1.1f + 0.055f * float(j));
      const float horizon = t.row(h).mu_horizon;
      altitude.push_back(h);
      mu_s.push_back(horizon + 0.0002f * float(j - 20));
    }
  std::vector<glm::vec3> batch(altitude.size());
  t.sun_batch(altitude.data(), mu_s.data(), altitude.size(), batch.data());  // more than one chunk, a remainder
  for (size_t i = 0; i < altitude.size(); ++i) {
    CAPTURE(altitude[i]);
    CAPTURE(mu_s[i]);
    CHECK(same_bits(batch[i], t.sun(altitude[i], mu_s[i])));
  }
}

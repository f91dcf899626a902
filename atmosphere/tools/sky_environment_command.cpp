// sky-environment: the prefiltered specular environment against brute-force
// integration of the sky, its bake cost and what its schedule costs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "atmosphere/sky_composite.h"
#include "atmosphere/sky_environment.h"
#include "atmosphere/sky_lighting.h"
#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_commands.h"
#include "engine/cli/cli_common.h"
#include "engine/core/luminance.h"
#include "engine/core/math_constants.h"
#include "engine/output/percentile.h"
#include "engine/shading/brdf.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/ggx_sampling.h"
#include "engine/shading/sh_lighting.h"

namespace cr {

namespace {

// n directions spread evenly over the sphere (spherical Fibonacci).
std::vector<glm::vec3> sphere_directions(int n) {
  std::vector<glm::vec3> d;
  for (int i = 0; i < n; ++i) {
    const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
    const float a = float(i) * 2.39996323f;
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    d.emplace_back(r * std::cos(a), y, r * std::sin(a));
  }
  return d;
}

// The un-prefiltered sky through a GGX lobe around unit n seen from unit v,
// by `samples` importance-sampled half vectors with no filtering: per sample
// the radiance of its reflected direction and a weight, summed in double.
// lobe: Karis' prefilter integral with n = v (weight n.l, normalised);
// metal: the white metal's reflected radiance, (1/N) sum L f n.l / pdf.
struct LobeReference {
  glm::vec3 lobe{0.0f};
  glm::vec3 metal{0.0f};
};
LobeReference reference_lobe(const SkyFrame& f, const glm::vec3& n, const glm::vec3& v, float roughness,
                             int samples) {
  const float alpha = std::max(roughness * roughness, kMinRoughness * kMinRoughness);
  glm::vec3 t, b;
  orthonormal_frame(n, t, b);
  thread_local std::vector<float> dx, dy, dz, wl, wm;
  thread_local std::vector<glm::vec3> l;
  for (auto* a : {&dx, &dy, &dz, &wl, &wm}) a->assign(size_t(samples) * 2, 0.0f);
  l.resize(size_t(samples) * 2);
  const float nv = glm::dot(n, v);
  for (int i = 0; i < samples; ++i) {
    const glm::vec3 hl = ggx_half_vector(hammersley(uint32_t(i), uint32_t(samples)), alpha);
    const glm::vec3 h = hl.x * t + hl.y * b + hl.z * n;
    // Lobe (v = n): l = reflect(-n, h).
    const glm::vec3 ll = 2.0f * hl.z * h - n;
    const size_t j = size_t(i) * 2;
    dx[j] = ll.x;
    dy[j] = ll.y;
    dz[j] = ll.z;
    wl[j] = std::max(glm::dot(ll, n), 0.0f);
    // Metal: l = reflect(-v, h), weight Vis 4 n.l v.h / n.h (F = 1).
    const float vh = glm::dot(v, h);
    const glm::vec3 lm = 2.0f * vh * h - v;
    const float nl = glm::dot(lm, n);
    dx[j + 1] = lm.x;
    dy[j + 1] = lm.y;
    dz[j + 1] = lm.z;
    wm[j + 1] = nl > 0.0f && vh > 0.0f ? smith_visibility(nl, nv, alpha) * 4.0f * nl * vh / hl.z : 0.0f;
  }
  sky_radiance_batch(f, l.size(), dx.data(), dy.data(), dz.data(), l.data());
  glm::dvec3 lobe(0.0), metal(0.0);
  double w = 0.0;
  for (size_t j = 0; j < l.size(); ++j) {
    lobe += double(wl[j]) * glm::dvec3(l[j]);
    w += double(wl[j]);
    metal += double(wm[j]) * glm::dvec3(l[j]);
  }
  return {glm::vec3(lobe / std::max(w, 1e-30)), glm::vec3(metal / double(samples))};
}

// What shading reads for the white metal at (n, v): the environment along
// the dominant direction times A + B (shade_surface.cpp's rule).
glm::vec3 shaded_metal(const SpecularEnvironment& env, const glm::vec3& n, const glm::vec3& v, float roughness) {
  const float r = std::max(roughness, kMinRoughness), alpha = r * r;
  const float nv = glm::dot(n, v);
  const glm::vec3 refl = 2.0f * nv * n - v;
  const EnvironmentBrdf e = environment_brdf(r, nv);
  return env.sample(refl + (n - refl) * alpha, r) * (e.a + e.b);
}

float relative(const glm::vec3& a, const glm::vec3& ref) {
  const float y = luminance(ref);
  return y > 0.0f ? std::abs(luminance(a) - y) / y : 0.0f;
}

struct ErrorSum {
  double sum = 0.0, worst = 0.0;
  int n = 0;
  void add(double e) {
    sum += e;
    worst = std::max(worst, e);
    ++n;
  }
  double mean() const { return n ? sum / n : 0.0; }
};

// The bake, split into `slices` calls as the schedule splits it; returns each call's time.
std::vector<double> time_environment(const SkyFrame& f, const AtmosphereSettings& s, int slices, JobSystem& jobs) {
  EnvironmentPrefilter p(s.environment_size, s.environment_levels, s.environment_samples);
  std::vector<double> ms;
  for (int q = 0; q < slices; ++q) {
    const double t0 = now_ms();
    p.run(p.slice_begin(q, slices), p.slice_begin(q + 1, slices), sky_environment_radiance(f), jobs, "bench");
    ms.push_back(now_ms() - t0);
  }
  return ms;
}

}  // namespace

int sky_environment_command(const std::vector<std::string>& args) {
  ArgParser p("sky-environment", "cpurender sky-environment [options]",
              "The prefiltered specular environment against integrating the un-prefiltered sky through each\n"
              "roughness's GGX lobe (mean and worst relative error, lobe and white metal), its bake time (full,\n"
              "worst slice, amortised; 1 and all threads) and the error its schedule costs along a camera path.");
  add_sky_setup_options(p);
  p.option("repeat", "N", "runs per timing (medians)", "7")
      .option("directions", "N", "directions over the sphere", "96")
      .option("samples", "N", "reference samples per lobe", "8192")
      .option("frames", "N", "frames of the schedule path", "240");
  if (!p.parse(args, 0, 0)) return 0;
  const SkySetup setup = load_sky_setup(p);
  const AtmosphereSettings& s = setup.settings;
  const unsigned all_threads = threads_option(p);
  const int repeat = p.get_int("repeat", 1, 1000);
  const int ndirs = p.get_int("directions", 4, 100000);
  const int samples = p.get_int("samples", 16, 1 << 20);
  const int frames = p.get_int("frames", 2, 100000);
  const glm::vec3 e = solar_sun_illuminance();
  const double altitude = 2.0;
  const Camera cam = horizon_camera(altitude, 16, 9);
  const std::vector<int> sizes = EnvironmentPrefilter::level_sizes(s.environment_size, s.environment_levels);
  std::printf("sky-environment: preset %s, octahedral %d levels (", setup.scene.preset.c_str(), s.environment_levels);
  for (size_t k = 0; k < sizes.size(); ++k) std::printf("%s%d", k ? ", " : "", sizes[k]);
  std::printf("), %d samples/texel at level 0's size, period %d, %d slices\n", s.environment_samples,
              s.environment_schedule.period, s.environment_schedule.slices);

  JobSystem jobs(all_threads);
  const std::vector<glm::vec3> dirs = sphere_directions(ndirs);
  std::vector<float> roughness;
  for (int i = 0; i <= 10; ++i) roughness.push_back(float(i) / 10.0f);
  for (double zenith : {40.0, 80.0}) {
    SkyCase c = make_sky_case(setup, s);
    update_sky_case(c, 0, cam, sun_at_zenith_angle(zenith), e, jobs);
    const double t0 = now_ms();
    const auto env = bake_sky_environment(c.frame, s, jobs);
    const double bake = now_ms() - t0;
    // The ground below the horizon is the sky-view LUT's: against albedo / pi (transmitted sun + SH sky irradiance).
    const glm::vec3 up = c.frame.up;
    const glm::vec3 nadir = sky_radiance(c.frame, -up, false);
    LightEnvironment light;
    fill_light_environment(c.frame, light);
    const glm::vec3 e_sky = sh_irradiance(light.ambient_sh, up);
    const glm::vec3 e_sun = light.sun_illuminance * std::max(glm::dot(light.sun_direction, up), 0.0f);
    const glm::vec3 lambert = c.frame.model.ground_albedo * (e_sun + e_sky) / kPi;
    std::printf("\nsun zenith %.0f deg, camera %.0f m (bake %.2f ms, %u threads): nadir ground %.0f cd/m^2 in the LUT, "
                "albedo/pi (sun %.0f + sky %.0f lx) = %.0f (ratio %.3f)\n",
                zenith, altitude, bake, all_threads, double(luminance(nadir)), double(luminance(e_sun)),
                double(luminance(e_sky)), double(luminance(lambert)), double(luminance(nadir) / luminance(lambert)));
    std::printf("%-10s %-6s %22s %30s\n", "roughness", "level", "lobe mean / max %",
                "white metal n.v=0.5 mean / max %");
    for (float r : roughness) {
      ErrorSum lobe, metal;
      std::vector<LobeReference> refs(dirs.size());
      std::vector<glm::vec3> views(dirs.size());
      jobs.parallel_for("reference", dirs.size(), 1, [&](size_t b, size_t en) {
        for (size_t i = b; i < en; ++i) {
          glm::vec3 t, bt;
          orthonormal_frame(dirs[i], t, bt);
          views[i] = 0.5f * dirs[i] + 0.8660254f * t;
          refs[i] = reference_lobe(c.frame, dirs[i], views[i], r, samples);
        }
      });
      for (size_t i = 0; i < dirs.size(); ++i) {
        lobe.add(relative(env->sample(dirs[i], r), refs[i].lobe));
        metal.add(relative(shaded_metal(*env, dirs[i], views[i], r), refs[i].metal));
      }
      std::printf("%-10.2f %-6.2f %10.2f / %-10.2f %14.2f / %-10.2f\n", double(r), double(r) * (s.environment_levels - 1),
                  100 * lobe.mean(), 100 * lobe.worst, 100 * metal.mean(), 100 * metal.worst);
    }
  }

  // Bake cost: whole, per slice, amortised over the period, at 1 and N threads.
  std::vector<unsigned> thread_counts{1};
  if (all_threads > 1) thread_counts.push_back(all_threads);
  std::printf("\n%-10s %10s %12s %16s\n", "threads", "full", "worst slice", "amortised/frame");
  for (unsigned threads : thread_counts) {
    JobSystem tj(threads);
    SkyCase c = make_sky_case(setup, s);
    update_sky_case(c, 0, cam, sun_at_zenith_angle(40.0), e, tj);
    std::vector<double> full, worst;
    for (int r = 0; r < repeat; ++r) {
      full.push_back(time_environment(c.frame, s, 1, tj)[0]);
      const std::vector<double> sl = time_environment(c.frame, s, s.environment_schedule.slices, tj);
      worst.push_back(*std::max_element(sl.begin(), sl.end()));
    }
    std::printf("%-10u %8.2fms %10.2fms %14.3fms\n", threads, median(full), median(worst),
                median(full) / s.environment_schedule.period);
  }

  // What the schedule costs: along sky-bench's path (3 m/frame, climbing 0.5 m/frame, turning, the sun setting
  // 0.1 deg/frame), the published environment against one baked from the same frame's sky every frame.
  AtmosphereSettings full = s;
  full.full_schedule = true;
  SkyCase c = make_sky_case(setup, s);
  SkyEnvironment amortised(s), every(full);
  ErrorSum error;
  double worst_frame = 0.0, work = 0.0, worst_work = 0.0;
  int worst_at = 0;
  std::map<std::string, int> causes;
  for (int f = 0; f < frames; ++f) {
    update_sky_case(c, f, path_camera(f, altitude, 16.0f / 9.0f), path_sun(f), e, jobs);
    const uint64_t upstream = c.luts->version(LutKind::MultiScattering);
    const EnvironmentWork wa = amortised.plan(c.plan, upstream), wf = every.plan(c.plan, upstream);
    amortised.run(wa, c.plan, upstream, c.frame, jobs);
    every.run(wf, c.plan, upstream, c.frame, jobs);
    if (wa.active) ++causes[wa.cause];
    work += amortised.frame_ms();
    worst_work = std::max(worst_work, amortised.frame_ms());
    ErrorSum frame_error;
    for (const glm::vec3& d : dirs)
      for (int k = 0; k < s.environment_levels; ++k) {
        const float r = amortised.front()->roughness(k);
        frame_error.add(relative(amortised.front()->sample(d, r), every.front()->sample(d, r)));
      }
    if (frame_error.mean() > error.worst) worst_at = f;
    error.add(frame_error.mean());
    worst_frame = std::max(worst_frame, frame_error.worst);
  }
  std::printf("\nschedule along a %d-frame path (3 m/frame, climbing 0.5 m/frame, sun setting 0.1 deg/frame), vs a "
              "rebake every frame:\nmean rel. error %.3f%%, worst-frame mean %.3f%% (frame %d), worst sample %.3f%%; "
              "environment work per frame (%u threads): mean %.3f ms, worst %.3f ms\nupdates:",
              frames, 100 * error.mean(), 100 * error.worst, worst_at, 100 * worst_frame, all_threads, work / frames, worst_work);
  for (const auto& [k, n] : causes) std::printf(" %s x%d", k.c_str(), n);
  std::printf("\n");
  return 0;
}

}  // namespace cr

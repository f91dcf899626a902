// sky-bench: what the LUTs and the composite cost, and what amortising the
// LUT updates costs in error.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "atmosphere/sky_composite.h"
#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_commands.h"
#include "engine/cli/cli_common.h"
#include "engine/core/luminance.h"
#include "engine/core/math_constants.h"
#include "engine/output/percentile.h"
#include "engine/render/composite_strips.h"
#include "engine/render/frame_buffers.h"

namespace cr {

namespace {

struct ErrorStats {
  double mean = 0.0;
  double p95 = 0.0;
  size_t count = 0;
};

ErrorStats relative_error(const std::vector<glm::vec3>& test, const std::vector<glm::vec3>& ref,
                          const std::vector<bool>& mask) {
  std::vector<double> e;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!mask.empty() && !mask[i]) continue;
    const double yr = luminance(ref[i]);
    const double yt = luminance(test[i]);
    e.push_back(std::abs(yt - yr) / std::max(yr, 1e-9));
  }
  ErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  double sum = 0.0;
  for (double v : e) sum += v;
  s.mean = sum / double(e.size());
  s.p95 = percentile_nearest_rank(e, 95.0);
  return s;
}

// The time of each slice of one rebuild of one LUT, run by a copy of the
// scheduler (its published LUTs as upstream): the bakes of every wavelength
// group, their mixing and quantisation, as a frame would run them.
std::vector<double> time_rebuild(LutKind kind, const LutScheduler& base, const AtmosphereFrameInputs& in, int slices,
                                 JobSystem& jobs) {
  LutScheduler luts = base;
  AtmospherePlan plan;
  plan.frame = in.frame;
  plan.inputs = in;
  std::vector<double> times;
  for (int q = 0; q < slices; ++q) {
    LutWork& w = plan.work[size_t(kind)];
    w = {true, q == 0, q, q + 1, slices, q + 1 == slices, "bench"};
    luts.run(kind, plan, jobs);
    times.push_back(luts.frame_ms(kind));
  }
  return times;
}

// A synthetic frame: sky above the horizon, ground geometry below at the distance a flat plane would be
// (no geometry at all for an altitude of 0).
void fill_test_buffers(FrameBuffers& b, const Camera& cam, double altitude) {
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      const glm::vec3 d = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, b.width, b.height);
      const size_t i = b.index(x, y);
      if (altitude > 0.0 && d.y < -1e-4f) {
        b.distance[i] = float(std::min(altitude / -double(d.y), 3e5));
        b.depth[i] = cam.znear / b.distance[i];
        b.color[i] = glm::vec3(0.1f, 0.12f, 0.08f) * 20000.0f;
      } else {
        b.distance[i] = std::numeric_limits<float>::infinity();
        b.depth[i] = 0.0f;
        b.color[i] = glm::vec3(0.0f);
      }
    }
}

// Process CPU time: on a shared machine the wall time of a job also counts other people's work.
double cpu_ms() { return 1000.0 * double(std::clock()) / double(CLOCKS_PER_SEC); }

struct CompositeTime {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;  // all threads together
};

CompositeTime time_composite(const SkyFrame& f, FrameBuffers& b, JobSystem& jobs) {
  const double t0 = now_ms(), c0 = cpu_ms();
  // Split as the engine's composite pass splits it.
  for_each_composite_strip(jobs, "composite", b.width, b.height,
                           [&](int x0, int y0, int x1, int y1) { composite_sky(f, b, x0, y0, x1, y1); });
  return {now_ms() - t0, cpu_ms() - c0};
}

// Median composite time over `repeat` runs on freshly filled buffers.
CompositeTime median_composite(const SkyFrame& f, const Camera& cam, double altitude, int width, int height,
                               int repeat, JobSystem& jobs) {
  FrameBuffers b;
  b.resize(width, height);
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeat; ++r) {
    fill_test_buffers(b, cam, altitude);
    const CompositeTime t = time_composite(f, b, jobs);
    wall.push_back(t.wall_ms);
    cpu.push_back(t.cpu_ms);
  }
  return {median(wall), median(cpu)};
}

}  // namespace

int sky_bench_command(const std::vector<std::string>& args) {
  ArgParser p("sky-bench", "cpurender sky-bench [options]",
              "Per-LUT bake times (full, worst slice, amortised over the period; 1 and all threads), the\n"
              "composite's time on the ground and from 400 km, and the error the profile's amortised schedules\n"
              "cost against a full rebuild every frame along a camera path under a setting sun.");
  add_sky_setup_options(p);
  p.option("repeat", "N", "runs per figure (medians)", "7")
      .option("width", "N", "composite width", "1280")
      .option("height", "N", "composite height", "720")
      .option("frames", "N", "frames of the amortisation path", "240");
  if (!p.parse(args, 0, 0)) return 0;
  const SkySetup setup = load_sky_setup(p);
  const unsigned all_threads = threads_option(p);
  const int repeat = p.get_int("repeat", 1, 1000);
  const int width = p.get_int("width", 16, 16384);
  const int height = p.get_int("height", 16, 16384);
  const int frames = p.get_int("frames", 2, 100000);
  const AtmosphereSettings& s = setup.settings;
  AtmosphereSettings full = s;
  full.full_schedule = true;
  const glm::vec3 e = solar_sun_illuminance();
  const double altitude = 2.0;
  const Camera cam = Camera::look_at(glm::dvec3(0.0, altitude, 0.0), glm::dvec3(1000.0, altitude - 40.0, 300.0),
                                     1.0471976f, float(width) / float(height), 0.1f);
  const glm::vec3 sun = glm::normalize(glm::vec3(0.6f, 0.5f, 0.4f));

  std::vector<unsigned> thread_counts{1};
  if (all_threads > 1) thread_counts.push_back(all_threads);
  std::printf("sky-bench: preset %s, %d wavelengths (%s), median of %d runs\n", setup.scene.preset.c_str(),
              s.spectral_samples, s.spectral_samples == 3 ? "RGB" : "spectral bands, mixed into RGB", repeat);
  const double o0 = now_ms();
  const ExplicitOrderChoice orders = explicit_orders_for(setup.scene.model, s);
  const double orders_ms = now_ms() - o0;
  std::printf("LUT sizes: transmittance %dx%d/%d steps, multi-scattering %dx%d x %d dirs x %d steps + %d explicit "
              "orders (f_ms up to %.3f; chosen in %.2f ms, once per atmosphere), sky-view %dx%d (%d-%d steps), AP %dx%dx%d (%g km/slice)\n",
              s.transmittance_width, s.transmittance_height, s.transmittance_steps, s.multiscattering_width,
              s.multiscattering_height, s.multiscattering_directions, s.multiscattering_steps, orders.orders,
              double(orders.max_fms), orders_ms, s.skyview_width, s.skyview_height,
              s.skyview_min_steps, s.skyview_max_steps, s.ap_width, s.ap_height, s.ap_depth, s.ap_km_per_slice);
  std::map<unsigned, std::array<double, kLutKinds>> full_ms, slice_ms;
  std::map<unsigned, CompositeTime> composite_ms, space_ms;
  // The space fallback: from 400 km, looking at the limb (sky-view LUT seen from space; no geometry).
  const double orbit = 400e3;
  const Camera orbit_cam = Camera::look_at(glm::dvec3(0.0, orbit, 0.0), glm::dvec3(2200e3, 0.0, 0.0), 1.0471976f,
                                           float(width) / float(height), 1.0f);
  double space_lut_ms = 0.0;
  for (unsigned threads : thread_counts) {
    JobSystem jobs(threads);
    SkyCase c = make_sky_case(setup, full);
    update_sky_case(c, 0, cam, sun, e, jobs);
    const AtmosphereFrameInputs in = c.plan.inputs;
    for (int k = 0; k < kLutKinds; ++k) {
      std::vector<double> f, sl;
      const int slices = s.schedule[size_t(k)].slices;
      for (int r = 0; r < repeat; ++r) {
        f.push_back(time_rebuild(LutKind(k), *c.luts, in, 1, jobs)[0]);
        const std::vector<double> parts = time_rebuild(LutKind(k), *c.luts, in, slices, jobs);
        sl.push_back(*std::max_element(parts.begin(), parts.end()));
      }
      full_ms[threads][size_t(k)] = median(f);
      slice_ms[threads][size_t(k)] = median(sl);
    }
    composite_ms[threads] = median_composite(c.frame, cam, altitude, width, height, repeat, jobs);
    SkyCase space = make_sky_case(setup, full);
    const double s0 = now_ms();
    update_sky_case(space, 0, orbit_cam, sun, e, jobs);
    if (threads == thread_counts.back()) space_lut_ms = now_ms() - s0;
    space_ms[threads] = median_composite(space.frame, orbit_cam, 0.0, width, height, repeat, jobs);
  }
  const unsigned hi = thread_counts.back();
  std::printf("\n%-20s %10s %10s %7s %7s %12s %14s\n", "LUT", "full 1T", "full NT", "period", "slices",
              "worst slice", "amortised/frm");
  double sum1 = 0, sumN = 0, amortised = 0;
  for (int k = 0; k < kLutKinds; ++k) {
    const LutSchedule& sc = s.schedule[size_t(k)];
    const double a = full_ms[hi][size_t(k)] / sc.period;
    sum1 += full_ms[1][size_t(k)];
    sumN += full_ms[hi][size_t(k)];
    amortised += a;
    std::printf("%-20s %8.2fms %8.2fms %7d %7d %10.2fms %12.3fms\n", lut_name(LutKind(k)), full_ms[1][size_t(k)],
                full_ms[hi][size_t(k)], sc.period, sc.slices, slice_ms[hi][size_t(k)], a);
  }
  std::printf("%-20s %8.2fms %8.2fms %7s %7s %12s %12.3fms\n", "all four", sum1, sumN, "", "", "", amortised);
  std::printf("(NT = %u threads; amortised = full NT / period, the cost when the inputs change every frame)\n", hi);
  std::printf("composite %dx%d (sky + aerial perspective): %.2f ms 1T, %.2f ms %uT wall (%.2f / %.2f ms CPU)\n",
              width, height, composite_ms[1].wall_ms, composite_ms[hi].wall_ms, hi, composite_ms[1].cpu_ms,
              composite_ms[hi].cpu_ms);
  std::printf("composite %dx%d from %.0f km (space fallback, sky only): %.2f ms 1T, %.2f ms %uT wall (%.2f / %.2f ms "
              "CPU); its four LUTs %.2f ms %uT\n",
              width, height, orbit / 1000.0, space_ms[1].wall_ms, space_ms[hi].wall_ms, hi, space_ms[1].cpu_ms,
              space_ms[hi].cpu_ms, space_lut_ms, hi);

  // What amortisation costs: the profile's schedules against a full rebuild every frame,
  // along a camera path (walking, turning, climbing) under a moving sun.
  JobSystem jobs(all_threads);
  SkyCase amortised_case = make_sky_case(setup, s);
  SkyCase full_case = make_sky_case(setup, full);
  const int pw = 160, ph = 90;
  FrameBuffers ba, bf;
  std::vector<double> means, p95s, work;
  std::map<std::string, int> causes;
  for (int f = 0; f < frames; ++f) {
    const Camera pc = path_camera(f, altitude, float(pw) / float(ph));
    update_sky_case(amortised_case, f, pc, path_sun(f), e, jobs);
    update_sky_case(full_case, f, pc, path_sun(f), e, jobs);
    double frame_work = 0.0;
    for (int k = 0; k < kLutKinds; ++k) {
      if (amortised_case.plan.work[size_t(k)].active) {
        frame_work += amortised_case.luts->frame_ms(LutKind(k));
        ++causes[std::string(lut_name(LutKind(k))) + ":" + amortised_case.plan.work[size_t(k)].cause];
      }
    }
    work.push_back(frame_work);
    ba.resize(pw, ph);
    bf.resize(pw, ph);
    fill_test_buffers(ba, pc, pc.position.y);
    fill_test_buffers(bf, pc, pc.position.y);
    composite_sky(amortised_case.frame, ba, 0, 0, pw, ph);
    composite_sky(full_case.frame, bf, 0, 0, pw, ph);
    const ErrorStats es = relative_error(ba.color, bf.color, {});
    means.push_back(es.mean);
    p95s.push_back(es.p95);
  }
  double mean_err = 0.0, mean_work = 0.0;
  for (double v : means) mean_err += v;
  for (double v : work) mean_work += v;
  std::printf("\namortisation along a %d-frame path (3 m/frame, 0.2 deg/frame turn, sun setting 0.1 deg/frame),\n"
              "%dx%d, vs a full rebuild every frame: mean rel. error %.3f%%, worst-frame p95 %.3f%%\n",
              frames, pw, ph, 100 * mean_err / frames, 100 * *std::max_element(p95s.begin(), p95s.end()));
  std::printf("measured LUT work per frame (%u threads): mean %.3f ms, worst frame %.3f ms\nupdates:", all_threads,
              mean_work / frames, *std::max_element(work.begin(), work.end()));
  for (const auto& [k, n] : causes) std::printf(" %s x%d", k.c_str(), n);
  std::printf("\n");
  return 0;
}

}  // namespace cr

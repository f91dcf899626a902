// `cpurender bench`: frame-time benchmark of the default scene and any glTF
// files, at 1 thread and at all threads, with throughput and speedup.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/paths.h"
#include "engine/output/atomic_file.h"
#include "engine/output/percentile.h"

namespace cr {

namespace {

struct BenchResult {
  std::vector<double> frame_ms;
  std::map<std::string, std::vector<double>> pass_ms;
  uint64_t triangles = 0, pixels_shaded = 0;
};

BenchResult run_bench(const RunSetup& setup, unsigned threads, int frames, int warmup,
                      const PluginRegistry& registry) {
  JobSystem jobs(threads);
  Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
  attach_playback(renderer, setup);
  BenchResult r;
  for (int f = 0; f < warmup + frames; ++f) {
    // Frames follow the scene's camera path (a static camera for most scenes).
    const FrameRecord& rec = renderer.render_frame(f);
    if (f < warmup) continue;
    r.frame_ms.push_back(rec.frame_ms);
    for (const PassTiming& p : rec.passes) r.pass_ms[p.name].push_back(p.ms());
    r.triangles = rec.raster.value("triangles_in", uint64_t(0));
    r.pixels_shaded = rec.raster.value("pixels_shaded", uint64_t(0));
  }
  return r;
}

}  // namespace

int bench_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser p("bench", "cpurender bench [GLTF_OR_SCENE...] [options]",
              "Renders each scene (the default scene first) for N frames at 1 thread and at all threads\n"
              "(after warm-up frames) and prints triangles, pixels, median and p95 ms per pass,\n"
              "Mtriangles/s, Mpixels/s shaded and the multi-thread speedup.");
  p.option("profile", "NAME|FILE", "render profile", "desktop")
      .option("resolution", "WxH", "resolution", "1280x720")
      .option("frames", "N", "measured frames per run", "20")
      .option("warmup", "N", "unmeasured frames first", "2")
      .option("threads", "N", "the multi-thread run's thread count (default: all cores)")
      .option("json", "FILE", "also write the results as JSON")
      .flag("no-default", "skip the default scene");
  add_model_access_options(p);
  if (!p.parse(args, 0, 64)) return 0;
  const int frames = p.get_int("frames", 1, 100000), warmup = p.get_int("warmup", 0, 1000);
  const unsigned max_threads = threads_option(p);
  const auto [w, h] = parse_resolution(p.get("resolution"), "bench");

  std::vector<std::string> scenes;
  if (!p.has("no-default")) scenes.push_back(default_scene_path());
  for (const std::string& s : p.positional()) scenes.push_back(s);
  if (scenes.empty()) throw UsageError("bench: nothing to benchmark");

  nlohmann::json out = nlohmann::json::array();
  for (const std::string& scene : scenes) {
    RunSetup setup = load_run(scene, p.get("profile"), registry, w, h, 1, model_access(p));
    std::printf("\n%s  (%dx%d, %zu triangles, %d frames + %d warm-up)\n", scene.c_str(), w, h,
                setup.scene->triangle_count(), frames, warmup);
    std::vector<unsigned> thread_counts = {1};
    if (max_threads > 1) thread_counts.push_back(max_threads);
    std::vector<BenchResult> results;
    for (unsigned t : thread_counts) results.push_back(run_bench(setup, t, frames, warmup, registry));

    std::printf("  %-28s", "pass (median / p95 ms)");
    for (unsigned t : thread_counts) std::printf("   %2u thread%s        ", t, t == 1 ? " " : "s");
    std::printf("\n");
    for (const auto& [name, v1] : results[0].pass_ms) {
      std::printf("  %-28s", name.c_str());
      for (const BenchResult& r : results) {
        auto it = r.pass_ms.find(name);
        if (it == r.pass_ms.end()) std::printf("   %8s           ", "-");
        else std::printf("   %8.2f / %-8.2f", median(it->second), percentile_nearest_rank(it->second, 95));
      }
      std::printf("\n");
    }
    nlohmann::json entry = {{"scene", scene}, {"width", w}, {"height", h},
                            {"triangles", setup.scene->triangle_count()}, {"runs", nlohmann::json::array()}};
    std::printf("  %-28s", "frame");
    for (const BenchResult& r : results)
      std::printf("   %8.2f / %-8.2f", median(r.frame_ms), percentile_nearest_rank(r.frame_ms, 95));
    std::printf("\n");
    for (size_t i = 0; i < results.size(); ++i) {
      const BenchResult& r = results[i];
      const double ms = median(r.frame_ms);
      const double mtris = double(r.triangles) / (ms * 1e3), mpix = double(r.pixels_shaded) / (ms * 1e3);
      std::printf("  %2u thread%s: %.2f ms/frame median, %.1f Mtriangles/s, %.1f Mpixels/s shaded\n",
                  thread_counts[i], thread_counts[i] == 1 ? " " : "s", ms, mtris, mpix);
      nlohmann::json run = {{"threads", thread_counts[i]},
                            {"frame_ms_median", ms},
                            {"frame_ms_p95", percentile_nearest_rank(r.frame_ms, 95)},
                            {"mtriangles_per_s", mtris},
                            {"mpixels_shaded_per_s", mpix},
                            {"pixels_shaded", r.pixels_shaded}};
      for (const auto& [name, v] : r.pass_ms)
        run["passes"][name] = {{"median_ms", median(v)}, {"p95_ms", percentile_nearest_rank(v, 95)}};
      entry["runs"].push_back(run);
    }
    if (results.size() > 1) {
      const double speedup = median(results[0].frame_ms) / median(results[1].frame_ms);
      std::printf("  speedup %u threads vs 1: %.2fx\n", thread_counts[1], speedup);
      entry["speedup"] = speedup;
    }
    out.push_back(entry);
  }
  if (p.has("json")) write_file_atomic(p.get("json"), out.dump(2) + "\n");
  return 0;
}

}  // namespace cr

// fog-bench: per-pass fog times at the profile's resolution, with one thread
// and with --threads (default: all) threads: the median over frames after the
// first two (which allocate the buffers and the history). The fog steps run
// on their own after the engine's fog-free frame (depth, shadow map, light),
// as the plugin's passes do, so no other pass's jobs share their threads and
// the figures are the fog's alone; composite is the fog's per-pixel part.
#include <cstdio>

#include "engine/core/error.h"
#include "engine/output/percentile.h"
#include "engine/render/frame_view.h"
#include "engine/cli/cli_common.h"
#include "fog/tools/fog_command_common.h"
#include "fog/tools/fog_commands.h"

namespace cr {

int fog_bench_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser a("fog-bench", "cpurender fog-bench SCENE [options]",
              "Per-pass fog times (median over frames after the first two) at 1 thread and at --threads.");
  add_fog_command_options(a);
  a.option("frames", "N", "frames per run (>= 3)", "10")
      .option("sun-turn", "DEG", "turn the sun's azimuth this much per frame (times moving-light frames)", "0");
  if (!a.parse(args, 1, 1)) return 0;
  FogRun run = load_fog_run(a, registry);
  const int frames = a.get_int("frames", 3, 10000);
  const double sun_turn = a.get_double("sun-turn", -180.0, 180.0);
  if (sun_turn != 0.0)
    run.description = with_turning_sun(
        run.description, make_frame_view(*run.scene, run.description, 0, run.profile.width, run.profile.height),
        frames, sun_turn);
  const unsigned all = threads_option(a);
  std::printf("fog-bench %s, %dx%d, median of %d frames\n", run.description.path.c_str(), run.profile.width,
              run.profile.height, frames - 2);
  std::printf("%-18s %12s %12s\n", "pass (ms)", "1 thread", (std::to_string(all) + " threads").c_str());
  const char* names[] = {"fog.density", "fog.lighting", "fog.reproject", "fog.filter", "fog.integrate",
                         "fog passes total", "fog composite"};
  constexpr int kRows = 7;
  double median_ms[2][kRows];
  size_t lit = 0, count = 0;
  // Of the measured frames (the last run's): lit, with a still view's
  // jitter-sequence mean instead of lighting, frozen.
  int lit_frames = 0, mean_frames = 0, frozen_frames = 0;
  const unsigned counts[2] = {1u, all};
  for (int c = 0; c < 2; ++c) {
    JobSystem jobs(counts[c]);
    Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(registry), jobs);
    FroxelFog fog(run.fog_profile, run.fog_scene);
    std::vector<double> ms[kRows];
    for (int f = 0; f < frames; ++f) {
      base.render_frame(f);
      FroxelTimes t;
      froxel_frame(fog, base.frame_view(f), base, jobs, &t);
      if (f < 2) continue;
      const FroxelFogStats& st = fog.stats();
      if (c == 1) {
        frozen_frames += st.lighting_frozen;
        mean_frames += st.jitter_complete && !st.lighting_frozen;
        lit_frames += !st.jitter_complete;
      }
      const double row[kRows] = {t.density, t.lighting, t.reproject, t.filter, t.integrate, t.passes(), t.composite};
      for (int r = 0; r < kRows; ++r) ms[r].push_back(row[r]);
    }
    for (int r = 0; r < kRows; ++r) median_ms[c][r] = median(ms[r]);
    lit = fog.stats().lit_froxels;
    count = fog.grid().count();
  }
  for (int r = 0; r < kRows; ++r) std::printf("%-18s %12.2f %12.2f\n", names[r], median_ms[0][r], median_ms[1][r]);
  std::printf("lit froxels after depth culling: %zu of %zu (%.0f%%)\n", lit, count,
              count ? 100.0 * double(lit) / double(count) : 0.0);
  std::printf("measured frames: %d lit, %d with the still view's jitter mean, %d frozen\n", lit_frames, mean_frames,
              frozen_frames);
  return 0;
}

}  // namespace cr

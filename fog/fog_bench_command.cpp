// fog-bench: per-pass fog times of the engine's frame graph at the profile's
// resolution, with one thread and with --threads (default: all) threads
// (mean over frames after the first, which allocates).
#include <cstdio>
#include <map>

#include "engine/core/error.h"
#include "fog/fog_command_common.h"
#include "fog/fog_commands.h"

namespace cr {

int fog_bench_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  const FogCommandArgs a = parse_fog_command_args(args, {"profile", "resolution", "frames", "threads"});
  const FogRun run = load_fog_run(a, registry);
  const int frames = a.get_int("frames", 8, 2, 10000);
  const unsigned all = unsigned(a.get_int("threads", int(JobSystem::default_thread_count()), 1, 1024));
  std::printf("fog-bench %s, %dx%d, %d frames\n", run.description.path.c_str(), run.profile.width,
              run.profile.height, frames);
  std::printf("%-16s %12s %12s\n", "pass (ms)", "1 thread", (std::to_string(all) + " threads").c_str());
  std::map<std::string, double> ms[2];
  std::vector<std::string> order;
  const unsigned counts[2] = {1u, all};
  for (int c = 0; c < 2; ++c) {
    JobSystem jobs(counts[c]);
    Renderer renderer(*run.scene, run.description, run.profile, registry.create_all(), jobs);
    for (int f = 0; f < frames; ++f) {
      const FrameRecord& r = renderer.render_frame(f);
      if (f == 0) continue;
      double fog_total = 0.0;
      for (const PassTiming& p : r.passes) {
        const bool is_fog = p.name.rfind("fog.", 0) == 0;
        if (!is_fog && p.name != "composite") continue;
        if (c == 0 && f == 1) order.push_back(p.name);
        ms[c][p.name] += p.ms() / double(frames - 1);
        if (is_fog) fog_total += p.ms();
      }
      ms[c]["fog passes total"] += fog_total / double(frames - 1);
    }
  }
  order.push_back("fog passes total");
  for (const std::string& n : order) std::printf("%-16s %12.2f %12.2f\n", n.c_str(), ms[0][n], ms[1][n]);
  std::printf("(composite is the engine's per-tile composite pass, all plugins)\n");
  return 0;
}

}  // namespace cr

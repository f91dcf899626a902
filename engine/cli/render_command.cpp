// `cpurender render`: renders frames of a scene and writes images and reports.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/paths.h"
#include "engine/output/chrome_trace.h"
#include "engine/output/run_status.h"
#include "engine/output/timing_report.h"
#include "engine/render/renderer.h"

namespace cr {

int render_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser p("render", "cpurender render [SCENE] [options]",
              "Renders frames of a scene (a scene .json or a bare .gltf/.glb; default: the generated\n"
              "default scene) and writes frame_NNNN.png / .exr, report.json and trace.json.");
  add_scene_options(p);
  p.option("out", "DIR", "output directory", "out")
      .option("format", "LIST", "comma-separated frame formats: png, exr, none", "png")
      .option("first-frame", "N", "first frame index of the camera path", "0")
      .flag("no-trace", "do not write the Chrome trace (trace.json)")
      .flag("quiet", "no progress output");
  if (!p.parse(args, 0, 1)) return 0;

  RunSetup setup = load_run_setup(p, registry);
  const std::string out = p.get("out");
  bool png = false, exr = false;
  for (const std::string& f : p.get_list("format")) {
    if (f == "png") png = true;
    else if (f == "exr") exr = true;
    else if (f != "none") throw UsageError("render: unknown --format '" + f + "' (png, exr, none)");
  }
  const int first = p.get_int("first-frame", 0, 1 << 20);
  const bool quiet = p.has("quiet");
  if (setup.plan && !quiet) std::cout << setup.plan->summary();
  std::filesystem::create_directories(out);

  JobSystem jobs(setup.threads);
  RunReport report = make_run_report(setup, jobs);
  // report.json says "running" until the trace, the last file, is written (run_status.h).
  report_run(out + "/report.json", report, [&] {
    Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
    renderer.keep_view_distances(exr);  // an EXR frame's depth channel
    attach_playback(renderer, setup);
    for (int f = first; f < first + setup.frames; ++f) {
      const FrameRecord& rec = renderer.render_frame(f);
      char name[64];
      std::snprintf(name, sizeof name, "/frame_%04d", f);
      if (png) write_frame_png(out + name + ".png", renderer.buffers());
      if (exr) write_frame_exr(out + name + ".exr", renderer.buffers());
      // After its files: a failed run's report lists exactly the frames on disk.
      report.frames.push_back(to_report_frame(rec));
      if (!quiet && setup.frames > 1)
        std::fprintf(stderr, "\rframe %d/%d  %.2f ms", f - first + 1, setup.frames, rec.frame_ms);
    }
    if (!quiet && setup.frames > 1) std::fprintf(stderr, "\n");
    if (!p.has("no-trace")) write_chrome_trace(out + "/trace.json", report);
  });
  if (!quiet) {
    std::cout << format_summary(report);
    std::cout << "wrote " << out << "/" << (png ? "frame_*.png " : "") << (exr ? "frame_*.exr " : "")
              << "report.json" << (p.has("no-trace") ? "" : " trace.json") << "\n";
  }
  return 0;
}

}  // namespace cr

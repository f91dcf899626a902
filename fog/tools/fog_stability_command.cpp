// fog-stability: the froxel fog over grids of extinction, anisotropy, camera
// speed and history weight against the ray-marched reference, written as a
// stability map (engine/output/stability_map.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/core/error.h"
#include "engine/output/stability_map.h"
#include "fog/tools/fog_commands.h"
#include "fog/tools/fog_stability.h"

namespace cr {

namespace {

const char* const kDescription =
    "Runs the froxel fog (the built-in profile: 8 px froxels or --froxel-size, 64 slices over 64 m) for\n"
    "--frames frames of a synthetic view: uniform fog of albedo 0.9 under a low sun, a tall wall casting a\n"
    "light shaft, the sky behind, the camera moving sideways at a constant speed. Two grids:\n"
    "  medium    extinction (1 / mean free path, log) x HG anisotropy g, still camera\n"
    "  temporal  camera speed (m/frame) x history weight (0: reprojection off), at --extinction and --g\n"
    "Per cell: mean / p95 relative luminance error of the last frame against the per-pixel ray-marched\n"
    "reference, the reference's convergence error (--samples against half as many) as its noise, NaN/Inf\n"
    "values in every frame's volume and image and in the reference, and of the froxels whose history was\n"
    "read, the share rejected (outside the previous frustum) or clamped to the 3x3 range (fallbacks\n"
    "history_rejected, history_clamped; means over the frames with history; with the clamp a moving camera\n"
    "reads only froxels whose 3x3 range is not one value). Writes OUT/stability.json;\n"
    "draw it with /usr/bin/python3 tools/stability/stability_map.py OUT/stability.json.\n"
    "Exit status: 0, or 1 when any value is non-finite.";

StabilityCell map_cell(int x, int y, const FogStabilityCell& s) {
  StabilityCell c;
  c.x = x;
  c.y = y;
  c.scored = true;
  c.error_mean = s.error.mean;
  c.error_p95 = s.error.p95;
  c.noise_mean = s.noise.mean;
  c.non_finite = s.non_finite + s.non_finite_reference;
  c.fallbacks = {{"history_rejected", s.history_rejected}, {"history_clamped", s.history_clamped}};
  c.details = {{"noise_p95", s.noise.p95},
               {"history_read", s.history_read},
               {"non_finite_fog", s.non_finite},
               {"non_finite_reference", s.non_finite_reference},
               {"passes_ms_per_frame", s.passes_ms},
               {"ref_ms", s.ref_ms}};
  return c;
}

}  // namespace

int fog_stability_command(const std::vector<std::string>& args, const PluginRegistry&) {
  ArgParser p("fog-stability", "cpurender fog-stability --out DIR [options]", kDescription);
  p.option("out", "DIR", "where stability.json goes")
      .option("grids", "NAME,...", "medium, temporal", "medium,temporal")
      .option("mean-free-path", "M,...", "mean free paths (medium grid)", "1,3.16,10,31.6,100,316,1000,3160,10000")
      .option("g", "G,...", "anisotropies (medium grid)", "-0.99,-0.9,-0.6,-0.3,0,0.3,0.6,0.9,0.99")
      .option("speed", "M,...", "camera speeds per frame (temporal grid)", "0,0.03,0.1,0.3,1,3,10")
      .option("history-weight", "W,...", "history weights, 0 = reprojection off (temporal grid)",
              "0,0.5,0.75,0.857143,0.95")
      .option("extinction", "PER_M", "extinction of the temporal grid", "0.05")
      .option("anisotropy", "G", "anisotropy of the temporal grid", "0.4")
      .option("froxel-size", "PX", "froxel size in pixels", "8")
      .option("frames", "N", "frames per cell (the last is measured)", "8")
      .option("resolution", "WxH", "frame size", "160x96")
      .option("samples", "N", "reference segments per pixel", "128")
      .option("threads", "N", "worker threads (default: all cores)");
  if (!p.parse(args, 0, 0)) return 0;
  if (!p.has("out")) throw UsageError("fog-stability: --out DIR is required");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> grids = p.get_list("grids");
  for (const std::string& g : grids)
    if (g != "medium" && g != "temporal") throw UsageError("--grids: unknown grid '" + g + "' (medium, temporal)");
  auto wanted = [&](const char* name) { return std::find(grids.begin(), grids.end(), name) != grids.end(); };
  const std::vector<double> mfps = p.get_doubles("mean-free-path", 1e-3, 1e30);
  const std::vector<double> gs = p.get_doubles("g", -0.999, 0.999);
  const std::vector<double> speeds = p.get_doubles("speed", 0.0, 1e4);
  const std::vector<double> weights = p.get_doubles("history-weight", 0.0, 0.999);
  FogStabilityCase base;
  base.extinction = float(p.get_double("extinction", 1e-30, 1e3));
  base.anisotropy = float(p.get_double("anisotropy", -0.999, 0.999));
  base.frames = p.get_int("frames", 1, 1000);
  base.froxel_size_px = p.get_int("froxel-size", 1, 256);
  FogStabilityOptions o;
  std::tie(o.width, o.height) = parse_resolution(p.get("resolution"), "fog-stability");
  o.samples = p.get_int("samples", 2, 1 << 16);
  const std::string out = p.get("out");
  std::filesystem::create_directories(out);
  JobSystem jobs(threads_option(p));

  StabilityMap map;
  map.method = "fog: HDRP-style froxels (built-in profile, " + std::to_string(base.froxel_size_px) + " px), " +
               std::to_string(base.frames) + " frames";
  map.ground_truth = "per-pixel ray-marched reference (" + std::to_string(o.samples) +
                     " segments/pixel; noise_mean is its difference from half as many)";
  map.command = "fog-stability";
  map.thresholds = {0.02, 0.05};
  map.settings = {{"resolution", std::to_string(o.width) + "x" + std::to_string(o.height)},
                  {"samples", o.samples},
                  {"frames", base.frames},
                  {"threads", jobs.thread_count()}};
  size_t non_finite = 0;
  std::printf("fog-stability: %dx%d, %d frames per cell, reference %d segments/pixel, %u threads\n", o.width,
              o.height, base.frames, o.samples, jobs.thread_count());
  std::printf("%-9s %9s %9s | %7s %7s %7s | %4s | %8s %8s | %7s %8s\n", "grid", "x", "y", "mean", "p95", "noise",
              "nan", "rejected", "clamped", "ms/frm", "ref_ms");
  auto run_grid = [&](const char* name, StabilityAxis x, StabilityAxis y, nlohmann::json fixed, auto case_at) {
    StabilityGrid g{name, std::move(x), std::move(y), {"history_rejected", "history_clamped"}, std::move(fixed), {}};
    for (size_t iy = 0; iy < g.y.values.size(); ++iy)
      for (size_t ix = 0; ix < g.x.values.size(); ++ix) {
        const FogStabilityCell s = evaluate_fog_stability(case_at(g.x.values[ix], g.y.values[iy]), o, jobs);
        const StabilityCell c = map_cell(int(ix), int(iy), s);
        non_finite += c.non_finite;
        std::printf("%-9s %9g %9g | %6.2f%% %6.2f%% %6.2f%% | %4zu | %8.4f %8.4f | %7.2f %8.1f\n", name,
                    g.x.values[ix], g.y.values[iy], 100 * c.error_mean, 100 * c.error_p95, 100 * c.noise_mean,
                    c.non_finite, s.history_rejected, s.history_clamped, s.passes_ms, s.ref_ms);
        std::fflush(stdout);
        g.cells.push_back(c);
      }
    map.grids.push_back(std::move(g));
  };
  if (wanted("medium"))
    run_grid("medium", StabilityAxis{"mean_free_path_m", "log", mfps}, StabilityAxis{"g", "linear", gs},
             {{"speed_m_per_frame", 0.0}, {"history_weight", base.history_weight}}, [&](double mfp, double g) {
               FogStabilityCase c = base;
               c.extinction = float(1.0 / mfp);
               c.anisotropy = float(g);
               return c;
             });
  if (wanted("temporal"))
    run_grid("temporal", StabilityAxis{"speed_m_per_frame", "symlog", speeds},
             StabilityAxis{"history_weight", "linear", weights},
             {{"extinction_per_m", base.extinction}, {"g", base.anisotropy}}, [&](double speed, double weight) {
               FogStabilityCase c = base;
               c.speed = float(speed);
               c.reprojection = weight > 0.0;
               if (c.reprojection) c.history_weight = float(weight);
               return c;
             });
  map.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_stability_json(out + "/stability.json", map);
  std::printf("%s/stability.json: %zu non-finite values, %.1f s\n", out.c_str(), non_finite, map.seconds);
  return non_finite == 0 ? 0 : 1;
}

}  // namespace cr

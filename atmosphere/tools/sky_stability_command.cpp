// sky-stability: the sky's LUT method over grids of sun zenith, camera
// altitude, density and Mie anisotropy against the path-traced reference,
// written as a stability map (engine/output/stability_map.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_commands.h"
#include "atmosphere/tools/sky_stability.h"
#include "engine/cli/cli_common.h"
#include "engine/core/error.h"
#include "engine/output/stability_map.h"

namespace cr {

namespace {

const char* const kDescription =
    "Evaluates the sky (the four LUTs rebuilt as the plugin's first frame builds them, then the panorama\n"
    "sky-accuracy views) over three grids:\n"
    "  zenith-altitude  sun zenith x camera altitude (0, then log-spaced up to 1000 km)\n"
    "  density          density scale of every constituent (log) x sun zenith, at --grid-altitude\n"
    "  mie-g            Mie anisotropy g x sun zenith, at --grid-altitude\n"
    "Per cell: mean / p95 relative luminance error against the path-traced reference and the reference's\n"
    "own noise (sky_accuracy's scoring), NaN/Inf values in every LUT, the sky, the aerial perspective of\n"
    "the ground (the per-pixel march from space) and the reference, and the share of the cell where each\n"
    "fallback engaged: space (camera above space_altitude), series_clamp (multi-scattering texels whose\n"
    "f_ms hit max_fms), orders_cap (max_explicit_orders reached with the series' share above tail_share),\n"
    "transmittance_underflow (transmittance texels at 0). Writes OUT/stability.json; draw it with\n"
    "/usr/bin/python3 tools/stability/stability_map.py OUT/stability.json.\n"
    "Exit status: 0, or 1 when any value is non-finite.";

std::vector<double> default_altitudes() {
  std::vector<double> a{0.0};
  for (int k = 0; k <= 12; ++k) a.push_back(std::pow(10.0, 0.5 * k));  // 1 m .. 1000 km, half decades
  return a;
}

std::string joined(const std::vector<double>& v) {
  std::string s;
  for (double x : v) {
    char b[32];
    std::snprintf(b, sizeof b, "%s%g", s.empty() ? "" : ",", x);
    s += b;
  }
  return s;
}

StabilityAxis axis(const char* name, const char* scale, std::vector<double> values) {
  return StabilityAxis{name, scale, std::move(values)};
}

StabilityCell map_cell(int x, int y, const SkyStabilityCell& s) {
  StabilityCell c;
  c.x = x;
  c.y = y;
  c.scored = s.score.scored > 0;
  c.error_mean = s.score.mean;
  c.error_p95 = s.score.p95;
  c.noise_mean = s.score.noise_mean;
  c.non_finite = s.non_finite();
  c.fallbacks = {{"space", s.space ? 1.0 : 0.0},
                 {"series_clamp", double(s.ms_clamped) / double(s.ms_texels)},
                 {"orders_cap", s.orders_capped ? 1.0 : 0.0},
                 {"transmittance_underflow", double(s.transmittance_underflow) / double(s.transmittance_texels)}};
  c.details = {{"scored_pixels", s.score.scored},
               {"dark_pixels", s.score.dark},
               {"bias_rms", s.score.bias_rms},
               {"non_finite_luts", s.non_finite_luts},
               {"non_finite_sky", s.non_finite_sky},
               {"non_finite_geometry", s.non_finite_geometry},
               {"non_finite_reference", s.non_finite_reference},
               {"max_fms", s.max_fms},
               {"explicit_orders", s.explicit_orders},
               {"lut_ms", s.lut_ms},
               {"ref_ms", s.ref_ms}};
  return c;
}

}  // namespace

int sky_stability_command(const std::vector<std::string>& args) {
  ArgParser p("sky-stability", "cpurender sky-stability --out DIR [options]", kDescription);
  add_sky_setup_options(p);
  p.option("out", "DIR", "where stability.json goes")
      .option("grids", "NAME,...", "zenith-altitude, density, mie-g", "zenith-altitude,density,mie-g")
      .option("sun-zenith", "DEG,...", "sun zenith angles", "0,15,30,45,60,75,90,105,120,135,150,165,180")
      .option("altitude", "M,...", "camera altitudes (zenith-altitude grid)", joined(default_altitudes()))
      .option("density", "X,...", "density scales", "0.01,0.0316,0.1,0.316,1,3.16,10,31.6,100")
      .option("mie-g", "G,...", "Mie anisotropies", "-0.99,-0.9,-0.6,-0.3,0,0.3,0.6,0.9,0.99")
      .option("grid-altitude", "M", "camera altitude of the density and mie-g grids", "1")
      .option("width", "N", "panorama width", "16")
      .option("height", "N", "panorama height", "8")
      .option("spp", "N", "reference paths per pixel", "512")
      .option("seed", "N", "reference random seed", "1")
      .option("spectrum", "rgb|spectral", "the reference's spectrum (rgb: the LUTs' own wavelengths)", "rgb");
  if (!p.parse(args, 0, 0)) return 0;
  if (!p.has("out")) throw UsageError("sky-stability: --out DIR is required");
  const double start = now_ms();
  const SkySetup setup = load_sky_setup(p);
  const std::vector<std::string> grids = p.get_list("grids");
  for (const std::string& g : grids)
    if (g != "zenith-altitude" && g != "density" && g != "mie-g")
      throw UsageError("--grids: unknown grid '" + g + "' (zenith-altitude, density, mie-g)");
  auto wanted = [&](const char* name) { return std::find(grids.begin(), grids.end(), name) != grids.end(); };
  const std::vector<double> zeniths = p.get_doubles("sun-zenith", 0.0, 180.0);
  const std::vector<double> altitudes = p.get_doubles("altitude", 0.0, 1e7);
  const std::vector<double> densities = p.get_doubles("density", 1e-4, 1e4);
  const std::vector<double> gs = p.get_doubles("mie-g", -0.999, 0.999);
  const double grid_altitude = p.get_double("grid-altitude", 0.0, 1e7);
  SkyStabilityOptions o;
  o.width = p.get_int("width", 2, 1024);
  o.height = p.get_int("height", 2, 1024);
  o.spp = p.get_int("spp", 1, 1 << 20);
  o.seed = uint64_t(p.get_int("seed", 0, 1 << 30));
  const std::string spectrum = p.get("spectrum");
  if (spectrum != "spectral" && spectrum != "rgb")
    throw UsageError("--spectrum: expected spectral or rgb, got '" + spectrum + "'");
  o.sampling = spectrum == "spectral" ? reference_sampling() : rgb_sampling();
  const std::string out = p.get("out");
  std::filesystem::create_directories(out);
  JobSystem jobs(threads_option(p));

  StabilityMap map;
  map.method = "sky: Hillaire 2020 LUTs (preset " + setup.scene.preset + ")";
  map.ground_truth = "path-traced reference (" + spectrum + ", " + std::to_string(o.spp) +
                     " paths/pixel; noise_mean is its relative standard error)";
  map.command = "sky-stability";
  map.thresholds = {0.02, 0.05};
  map.settings = {{"panorama", std::to_string(o.width) + "x" + std::to_string(o.height)},
                  {"spp", o.spp},
                  {"seed", o.seed},
                  {"spectral_samples", setup.settings.spectral_samples},
                  {"space_altitude_m", setup.settings.space_altitude},
                  {"max_fms", setup.settings.multiscattering_max_fms},
                  {"max_explicit_orders", setup.settings.multiscattering_max_explicit_orders},
                  {"threads", jobs.thread_count()}};
  const std::vector<std::string> fallbacks{"space", "series_clamp", "orders_cap", "transmittance_underflow"};
  size_t non_finite = 0;
  std::printf("sky-stability: preset %s, %dx%d panorama, %s reference at %d paths/pixel, %u threads\n",
              setup.scene.preset.c_str(), o.width, o.height, spectrum.c_str(), o.spp, jobs.thread_count());
  std::printf("%-15s %9s %9s | %7s %7s %7s | %4s | %5s %6s %5s %6s | %7s %8s\n", "grid", "x", "y", "mean", "p95",
              "noise", "nan", "space", "clamp", "cap", "t_zero", "lut_ms", "ref_ms");
  // Each grid: x values, y values and the cell at (x, y).
  auto run_grid = [&](const char* name, StabilityAxis x, StabilityAxis y, nlohmann::json fixed, auto cell_at) {
    StabilityGrid g{name, std::move(x), std::move(y), fallbacks, std::move(fixed), {}};
    for (size_t iy = 0; iy < g.y.values.size(); ++iy)
      for (size_t ix = 0; ix < g.x.values.size(); ++ix) {
        const SkyStabilityCell s = cell_at(g.x.values[ix], g.y.values[iy]);
        const StabilityCell c = map_cell(int(ix), int(iy), s);
        non_finite += c.non_finite;
        std::printf("%-15s %9g %9g | %6.2f%% %6.2f%% %6.2f%% | %4zu | %5d %6.3f %5d %6.3f | %7.1f %8.1f\n", name,
                    g.x.values[ix], g.y.values[iy], 100 * c.error_mean, 100 * c.error_p95, 100 * c.noise_mean,
                    c.non_finite, int(s.space), c.fallbacks[1].second, int(s.orders_capped), c.fallbacks[3].second,
                    s.lut_ms, s.ref_ms);
        std::fflush(stdout);
        g.cells.push_back(c);
      }
    map.grids.push_back(std::move(g));
  };
  const AtmosphereModel& model = setup.scene.model;
  if (wanted("zenith-altitude"))
    run_grid("zenith-altitude", axis("sun_zenith_deg", "linear", zeniths), axis("altitude_m", "symlog", altitudes),
             nlohmann::json::object(), [&](double zen, double alt) {
               return evaluate_sky_stability(model, setup.settings, zen, alt, o, jobs);
             });
  if (wanted("density"))
    run_grid("density", axis("sun_zenith_deg", "linear", zeniths), axis("density_scale", "log", densities),
             {{"altitude_m", grid_altitude}}, [&](double zen, double k) {
               return evaluate_sky_stability(with_density_scale(model, float(k)), setup.settings, zen,
                                             grid_altitude, o, jobs);
             });
  if (wanted("mie-g"))
    run_grid("mie-g", axis("sun_zenith_deg", "linear", zeniths), axis("mie_g", "linear", gs),
             {{"altitude_m", grid_altitude}}, [&](double zen, double g) {
               AtmosphereModel m = model;
               m.mie_g = float(g);
               return evaluate_sky_stability(m, setup.settings, zen, grid_altitude, o, jobs);
             });
  map.seconds = (now_ms() - start) / 1000.0;
  write_stability_json(out + "/stability.json", map);
  std::printf("%s/stability.json: %zu non-finite values, %.1f s\n", out.c_str(), non_finite, map.seconds);
  return non_finite == 0 ? 0 : 1;
}

}  // namespace cr

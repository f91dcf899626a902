// sky-luts: the four LUTs of one view as EXR and false-colour PNG.
#include <cstdio>
#include <string>
#include <vector>

#include "atmosphere/tools/lut_debug_output.h"
#include "atmosphere/tools/sky_case.h"
#include "atmosphere/tools/sky_commands.h"
#include "engine/cli/cli_common.h"

namespace cr {

int sky_luts_command(const std::vector<std::string>& args) {
  ArgParser p("sky-luts", "cpurender sky-luts --out DIR [options]",
              "Bakes the four LUTs for one view and sun and writes each as EXR and false-colour PNG.");
  add_sky_setup_options(p);
  p.option("out", "DIR", "output directory (required)")
      .option("altitude", "M", "camera altitude above the ground", "2")
      .option("sun-zenith", "DEG", "sun zenith angle", "60");
  if (!p.parse(args, 0, 0)) return 0;
  if (!p.has("out")) throw UsageError("sky-luts: needs --out DIR");
  const SkySetup setup = load_sky_setup(p);
  AtmosphereSettings full = setup.settings;
  full.full_schedule = true;
  JobSystem jobs(threads_option(p));
  SkyCase c = make_sky_case(setup, full);
  const double altitude = p.get_double("altitude", -1e4, 1e7);
  const double zenith = p.get_double("sun-zenith", 0.0, 180.0);
  update_sky_case(c, 0, horizon_camera(altitude, 16, 9), sun_at_zenith_angle(zenith), solar_sun_illuminance(), jobs);
  for (const std::string& path : write_lut_debug_views(*c.luts, p.get("out"))) std::printf("wrote %s\n", path.c_str());
  if (c.luts->multiscattering()->clamped_texels() > 0)
    std::printf("note: %d multi-scattering texels clamped f_ms to %.3f (largest f_ms %.3f)\n",
                c.luts->multiscattering()->clamped_texels(), double(full.multiscattering_max_fms),
                double(c.luts->multiscattering()->max_fms_seen()));
  return 0;
}

}  // namespace cr

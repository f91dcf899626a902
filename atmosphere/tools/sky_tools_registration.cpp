#include "atmosphere/tools/sky_commands.h"
#include "atmosphere/tools/sky_truth.h"
#include "engine/cli/command_registry.h"

namespace cr {

void register_sky_commands(CommandRegistry& commands, ModuleTruthRegistry& truths) {
  commands.add({"sky-accuracy", "sky: LUT method vs path-traced reference (error and time)", sky_accuracy_command});
  commands.add({"sky-bench", "sky: per-LUT bake times, composite time, amortisation error", sky_bench_command});
  commands.add({"sky-environment", "sky: prefiltered specular environment accuracy vs brute force, bake and schedule cost",
                sky_environment_command});
  commands.add({"sky-luts", "sky: write the four LUTs as EXR + false-colour PNG", sky_luts_command});
  commands.add({"sky-stability", "sky: error map over sun, altitude, density and Mie g; fallbacks; non-finite values",
                sky_stability_command});
  truths.add(sky_truth());
}

}  // namespace cr

#pragma once
// The atmosphere tools' CLI commands:
//   sky-accuracy     the LUT method against the path-traced reference: mean / p95 relative luminance error, times
//   sky-bench        per-LUT bake times (full, per slice, amortised; 1 and all threads), composite time,
//                    and the error amortisation costs along a camera path with a moving sun
//   sky-environment  the prefiltered specular environment against integrating the un-prefiltered sky
//                    per roughness, its bake time (full, per slice, amortised) and what its schedule costs
//   sky-luts         writes every LUT as EXR + false-colour PNG
//   sky-stability    the error map over sun zenith, altitude, density and Mie g, with the fallbacks engaged
// Each parses its options with ArgParser (--help lists them) and returns an exit code.
#include <string>
#include <vector>

namespace cr {

class CommandRegistry;
class ModuleTruthRegistry;

int sky_accuracy_command(const std::vector<std::string>& args);
int sky_bench_command(const std::vector<std::string>& args);
int sky_environment_command(const std::vector<std::string>& args);
int sky_luts_command(const std::vector<std::string>& args);
int sky_stability_command(const std::vector<std::string>& args);
// Adds the five commands, and the atmosphere's ground truth for sweep --truth (sky_truth.h).
void register_sky_commands(CommandRegistry& commands, ModuleTruthRegistry& truths);

}  // namespace cr

#pragma once
// The fog tools' CLI commands, each rendering through the plugins of `registry`.
#include <string>
#include <vector>

#include "engine/render/plugin_registry.h"

namespace cr {

class CommandRegistry;
class ModuleTruthRegistry;

// fog-accuracy SCENE [--profile P] [--resolution WxH] [--frame F] [--threads N] [--samples S] [--warmup W]
int fog_accuracy_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// fog-temporal SCENE [--profile P] [--resolution WxH] [--frames N] [--threads N] [--speed M] [--turn DEG]
//              [--sun-turn DEG]
int fog_temporal_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// fog-bench SCENE [--profile P] [--resolution WxH] [--frames N] [--threads N] [--sun-turn DEG]
int fog_bench_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// fog-stability --out DIR [--grids medium,temporal] [--resolution WxH] [--frames N] [--samples S] [--threads N]
int fog_stability_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// Adds fog-accuracy, fog-temporal, fog-bench and fog-stability, and the fog's
// ground truth for sweep --truth (fog_truth.h).
void register_fog_commands(CommandRegistry& commands, ModuleTruthRegistry& truths, const PluginRegistry& plugins);

}  // namespace cr

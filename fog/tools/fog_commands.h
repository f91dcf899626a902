#pragma once
// The fog plugin's CLI commands (registered by register_fog_plugin).
#include <string>
#include <vector>

#include "engine/render/plugin.h"

namespace cr {

// fog-accuracy SCENE [--profile P] [--resolution WxH] [--frame F] [--threads N] [--samples S] [--warmup W]
int fog_accuracy_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// fog-temporal SCENE [--profile P] [--resolution WxH] [--frames N] [--threads N] [--speed M] [--turn DEG]
//              [--sun-turn DEG]
int fog_temporal_command(const std::vector<std::string>& args, const PluginRegistry& registry);
// fog-bench SCENE [--profile P] [--resolution WxH] [--frames N] [--threads N] [--sun-turn DEG]
int fog_bench_command(const std::vector<std::string>& args, const PluginRegistry& registry);

}  // namespace cr

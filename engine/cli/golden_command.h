#pragma once
// `cpurender golden`: renders every shipped scene under every shipped profile
// at a small size, checks 1-thread vs N-thread renders are bit-identical and
// compares the kept frames with tests/golden/*.png under per-profile
// tolerances; --update rewrites the goldens that changed.
#include <string>
#include <vector>

namespace cr {

class PluginRegistry;

// args: the arguments after "golden". Returns 0 when every case passes (or
// the update succeeded), 1 when a case fails (a threshold, a missing golden,
// 1 vs N threads differing), 2 for a usage error or a case that cannot be
// rendered. In update mode nothing is written unless every case rendered and
// was deterministic.
int golden_command(const std::vector<std::string>& args, const PluginRegistry& registry);

}  // namespace cr

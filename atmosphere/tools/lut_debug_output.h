#pragma once
// Debug views of the published LUTs: each as a float EXR (linear values) and
// a false-colour PNG (magma; transmittance linearly, luminances on a 4-decade
// log scale). The aerial perspective volume is written as an atlas of its slices.
#include <string>
#include <vector>

#include "atmosphere/lut_scheduler.h"

namespace cr {

// Writes <dir>/<lut>.exr and <dir>/<lut>.png for every published LUT; returns the paths written.
std::vector<std::string> write_lut_debug_views(const LutScheduler& luts, const std::string& dir);

}  // namespace cr

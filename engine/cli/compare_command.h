#pragma once
// `cpurender compare A B [options]`: compares a reference image A with a test
// image B (both PNG or both EXR) and reports pixel and perceptual metrics.
#include <string>
#include <vector>

namespace cr {

// args: the arguments after "compare". Returns 0 when every metric is within
// its threshold, 1 when one is not (the heat map is written then), 2 for a
// usage error or unreadable input. Prints results to stdout, errors to stderr.
int compare_command(const std::vector<std::string>& args);

}  // namespace cr

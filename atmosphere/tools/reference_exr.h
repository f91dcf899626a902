#pragma once
// The path-traced reference's EXR file (sky-accuracy --out and --reference,
// sweep --truth's cache): linear colour, luminance Y and its standard error
// (full float), the colour ratios' noise, and which spectrum it was rendered
// with.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/tools/reference_merge.h"

namespace cr {

void write_reference_exr(const std::string& path, const std::vector<glm::vec3>& px, const std::vector<float>& y,
                         const std::vector<float>& noise, const std::vector<glm::vec2>& ratio_noise, bool spectral,
                         int w, int h);
// Its luminance, noise, colour and ratio noises into `r`; an InputError unless
// it is w x h and was rendered with the spectrum asked for.
void read_reference_exr(const std::string& path, int w, int h, bool spectral, ReferenceLuminance& r);

}  // namespace cr

#pragma once
// The atmosphere's ground truth for sweep --truth: the LUT sky of the point's
// atmosphere settings against the path-traced spectral reference, scored as
// sky-accuracy scores its panorama, for the scene's sun at the measured frame
// seen from the camera's altitude.
#include "engine/cli/module_truth.h"

namespace cr {

ModuleTruth sky_truth();

}  // namespace cr

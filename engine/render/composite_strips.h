#pragma once
// How the composite pass splits the frame: strips of full-width rows. A job
// then walks the colour and distance buffers in long sequential runs, which
// the hardware prefetcher follows; 64x64 tiles (64 short runs each) measured
// 1.2x slower for the fog composite at 1280x720.
#include <functional>

#include "engine/core/job_system.h"

namespace cr {

// Rows per strip: a multiple of the 8-pixel froxels and of 2x2 quads.
constexpr int kCompositeStripRows = 8;

// Calls fn(x0, y0, x1, y1) for every strip of a width x height frame, over the jobs.
void for_each_composite_strip(JobSystem& jobs, const char* name, int width, int height,
                              const std::function<void(int x0, int y0, int x1, int y1)>& fn);

}  // namespace cr

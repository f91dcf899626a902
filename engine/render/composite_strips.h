#pragma once
// How the composite pass splits the frame: strips of full-width rows. A job
// then walks the colour and distance buffers in long sequential runs, which
// the hardware prefetcher follows, and a froxel volume's rows are read by few
// strips. Against 64x64 tiles (64 short runs each) the fog composite at
// 1280x720 measured 0.81x with 32-row strips at 8 px froxels, 1.04x at 16 px.
#include <functional>

#include "engine/core/job_system.h"

namespace cr {

// Rows per strip for a frame: 32, fewer (multiples of 8, at least 8) where
// that would leave under four strips per worker to balance the load.
int composite_strip_rows(int height, unsigned threads);

// Calls fn(x0, y0, x1, y1) for every strip of a width x height frame, over the jobs.
void for_each_composite_strip(JobSystem& jobs, const char* name, int width, int height,
                              const std::function<void(int x0, int y0, int x1, int y1)>& fn);

}  // namespace cr

#pragma once
// What a profile's frames allocate, charged to a MemoryBudget before the
// renderer exists: the frame buffers (with a render scale below 1, those of
// the internal size and those of the output size), the visibility buffer, the
// multisampled edge pixels at their worst (every pixel an edge with a
// different surface at each sample) and the shadow maps.
#include "engine/core/memory_budget.h"
#include "engine/core/profile.h"

namespace cr {

void estimate_frame_memory(const Profile& profile, MemoryBudget& memory);

}  // namespace cr

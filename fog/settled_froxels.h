#pragma once
// A still view's settled froxels (profile `still_settled`, opt-in). In a
// still view (same camera, sun and density) only the jitter phase of each
// froxel's sample changes from frame to frame, and most froxels are fully
// lit or fully shadowed air: every sample gives exactly 1 or exactly 0.
// Where the history (the blend of all samples so far, at least two) holds
// that same 0 or 1 in a froxel and in all its lit neighbours of the 3x3x3
// box around it (columns x +- 1, y +- 1, slices k +- 1), the froxel is
// settled: its next samples are taken to be that value and are not lit.
// Neighbours sample other depth strata (the column hash), so an edge near a
// froxel shows in some neighbour's sample. What can be missed is an occluder
// thinner than a froxel that no sample so far touched: the lateral jitter is
// the same for every column in a frame, so a shadow sheet between two
// frames' sample offsets is missed in every column. Hence opt-in (README,
// "A still view").
#include <cstdint>
#include <vector>

#include "engine/core/job_system.h"
#include "fog/froxel_passes.h"

namespace cr {

// The spans (SliceSpan, froxel_passes.h) of `view` (whose lit slices are the
// history's) from `history`. `scratch` holds two bit masks per column and 64 slices between calls
// (kept to avoid reallocating them).
void unsettled_spans(const FroxelView& view, const std::vector<float>& history, JobSystem& jobs,
                     std::vector<uint64_t>& scratch, std::vector<SliceSpan>& spans);
// The same for a history of q15 codes (0 and 32767 are its 0 and 1).
void unsettled_spans(const FroxelView& view, const std::vector<uint16_t>& history, JobSystem& jobs,
                     std::vector<uint64_t>& scratch, std::vector<SliceSpan>& spans);

}  // namespace cr

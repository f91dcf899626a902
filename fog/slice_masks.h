#pragma once
// Bit masks of a froxel column's slices, 64 slices to a word: which slices
// hold exactly 0 and which exactly 1. Fully lit and fully shadowed air give
// exactly these values, so tests over a neighbourhood of froxels ("all 0 or
// all 1") become ANDs of masks (settled_froxels, reprojection's clamp).
#include <cstdint>

namespace cr {

// The lowest `count` bits set (count in [0, 64]).
inline uint64_t low_bits(int count) { return count >= 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1; }

// 64-bit words per mask for nz slices.
inline int mask_words(int nz) { return (nz + 63) / 64; }

// The masks of one column of `lit` values: out[0, words) the slices equal to
// 0 (either sign), out[words, 2 words) those equal to 1. Slices from `lit`
// on (unlit, or past the grid) are set in both: they do not take part.
void zero_one_masks(const float* values, int lit, int words, uint64_t* out);

}  // namespace cr

#pragma once
// Bit masks of a froxel column's slices, 64 slices to a word: which slices
// hold exactly 0 and which exactly 1. Fully lit and fully shadowed air give
// exactly these values, so tests over a neighbourhood of froxels ("all 0 or
// all 1") become ANDs of masks (settled_froxels, reprojection's clamp).
#include <cstddef>
#include <cstdint>

namespace cr {

// The lowest `count` bits set (count in [0, 64]).
inline uint64_t low_bits(int count) { return count >= 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1; }

// 64-bit words per mask for nz slices.
inline int mask_words(int nz) { return (nz + 63) / 64; }

// How many of word w's 64 slices lie below `lit`.
inline int lit_in_word(int lit, int w) {
  const int count = lit - 64 * w;
  return count < 0 ? 0 : count > 64 ? 64 : count;
}

// The masks of one column of `lit` values: out[0, words) the slices equal to
// 0 (either sign), out[words, 2 words) those equal to 1. Slices from `lit`
// on (unlit, or past the grid) are set in both: they do not take part.
void zero_one_masks(const float* values, int lit, int words, uint64_t* out);
// The same for q15 codes (sun_term_format.h): 0 and 32767, fully lit air's code.
void zero_one_masks(const uint16_t* codes, int lit, int words, uint64_t* out);

// Row y of a grid's column masks (2 words per column, as zero_one_masks
// lays them out; nx columns to a row, ny rows) ANDed with rows y - 1 and
// y + 1 (clamped at the grid's edges) into `vertical` (nx columns).
void and_rows(const uint64_t* masks, int nx, int ny, int y, int words, uint64_t* vertical);

// Word w of the slices [0, lit) of column x whose 3x3 columns (x - 1 .. x + 1
// of a row's and_rows result, clamped at the edges) do not all hold 0 or all
// hold 1 there.
inline uint64_t mixed_bits(const uint64_t* vertical, int nx, int x, int words, int w, int lit) {
  const std::size_t per_column = 2 * std::size_t(words);
  const uint64_t* l = vertical + std::size_t(x > 0 ? x - 1 : 0) * per_column;
  const uint64_t* m = vertical + std::size_t(x) * per_column;
  const uint64_t* r = vertical + std::size_t(x + 1 < nx ? x + 1 : x) * per_column;
  const std::size_t z = std::size_t(w), o = std::size_t(words + w);
  const uint64_t agree = (l[z] & m[z] & r[z]) | (l[o] & m[o] & r[o]);
  return ~agree & low_bits(lit_in_word(lit, w));
}

}  // namespace cr

#pragma once
// The 7-frame sample sequence of the froxel lighting (HDRP): frame i samples
// depth offset z = {7,3,11,5,9,1,13}[i]/14 (centroids of 7 equal strata) and a
// lateral offset from a 7-point hexagonal pattern (the centre and its six
// neighbours in a hexagonal close packing), in froxel units. A per-column
// hash offsets the depth stratum so neighbouring columns sample different
// depths (the 3x3 filter then averages them), as HDRP does per pixel.
#include <glm/glm.hpp>

namespace cr {

constexpr int kJitterFrames = 7;

struct FroxelJitter {
  glm::vec2 lateral{0.0f};  // froxel units, within (-0.5, 0.5)
  float depth = 0.5f;       // stratum offset in [0, 1)
};

// Sample i of the sequence (i taken modulo 7).
FroxelJitter froxel_jitter(int i);
// Deterministic per-column value in [0, 1).
float column_hash(int x, int y);

}  // namespace cr

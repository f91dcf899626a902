#pragma once
// Procedural density for fog volumes: fractal value noise (trilinear
// interpolation of hashed lattice values, smoothstep-weighted), pure integer
// hashing so it is identical on every run and thread.
#include <glm/glm.hpp>

namespace cr {

// Value noise in [0, 1] at p (lattice spacing 1).
float value_noise(const glm::vec3& p);
// Sum of `octaves` octaves (frequency x2, amplitude x0.5), normalised to [0, 1].
float fractal_noise(const glm::vec3& p, int octaves);

}  // namespace cr

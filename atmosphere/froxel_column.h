#pragma once
// A froxel column's slices shaded in one pass. The aerial-perspective LUT
// marches a whole column (march_media) and needs, per slice, the in-scattering
// and transmittance of that slice's steps alone: accumulate() + shade_split()
// per slice. shade_runs() gives exactly those, but takes the per-step lookup
// coordinates (transmittance row, sun and multiple-scattering texels) of the
// whole column from one loop that vectorizes instead of slice by slice.
#include <cstddef>

#include <glm/glm.hpp>

#include "atmosphere/scattering_march.h"

namespace cr {

// For each run r of `run` consecutive steps (steps [r * run, (r + 1) * run)):
// shaded[r] = shade_split(luts, ray, mu_s, nu) and transmittance[r] =
// ray.transmittance for ray = accumulate(luts, steps, r * run, (r + 1) * run, h0, mu),
// bit for bit. The step count must be a multiple of run.
void shade_runs(const AtmosphereLuts& luts, const MarchSteps& steps, float h0, float mu, float mu_s, float nu,
                size_t run, ShadedRay* shaded, glm::vec3* transmittance);

}  // namespace cr

#pragma once
// Display transform of linear radiance: exposure from EV100, a filmic
// tonemapper, the sRGB OETF and 8-bit quantisation. Per-pixel and inline so
// the renderer's resolve loops stay simple; all deterministic (no fast-math,
// the same operations in the same order for every pixel).
#include <cstddef>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/core/srgb.h"

namespace cr {

// Photometric exposure of the saturation-based sensitivity model (Lagarde and
// de Rousiers, "Moving Frostbite to PBR", 2014): a luminance of
// 1.2 * 2^EV100 cd/m^2 maps to 1.0.
inline float exposure_scale(float ev100) { return 1.0f / (1.2f * std::exp2(ev100)); }

// Narkowicz's 2015 fit of the ACES RRT+ODT ("ACES Filmic Tone Mapping
// Curve"), applied per channel to exposed values: cheap, monotone for x >= 0
// (its derivative's numerator has only positive coefficients), 0 -> 0, and it
// reaches 1 at x ~ 7.2, so highlights roll off instead of clipping at 1.0.
// Chosen over Hill's fit, which adds two 3x3 matrix products per pixel for
// a hue behaviour the project does not measure. NaN and negatives map to 0.
inline float tonemap_aces(float x) {
  if (!(x > 0.0f)) return 0.0f;
  if (x > 16.0f) return 1.0f;  // past the shoulder; keeps x*x finite for huge x
  const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return y < 1.0f ? y : 1.0f;
}


// One pixel: linear radiance (cd/m^2) to sRGB-encoded 8-bit RGB.
inline void resolve_pixel(const glm::vec3& radiance, float exposure, uint8_t* rgb_out) {
  for (int c = 0; c < 3; ++c) rgb_out[c] = quantize_unorm8(linear_to_srgb(tonemap_aces(radiance[c] * exposure)));
}

// `count` pixels of linear radiance to packed sRGB 8-bit RGB (3 bytes each).
void resolve_to_srgb8(const glm::vec3* hdr, size_t count, float ev100, uint8_t* rgb_out);

}  // namespace cr

#pragma once
// Texture lookups: an Image (RGBA8 mip chain) read through a glTF Sampler,
// following the OpenGL 4.6 rules (section 8.14): level of detail from the
// scale factor, magnification/minification filters, nearest or linear
// (trilinear) mip selection, and the three glTF wrap modes. sRGB images are
// decoded to linear per texel before filtering, as GPUs do.
#include <glm/glm.hpp>

#include "engine/scene/scene.h"

namespace cr {

// Level of detail lambda = log2(rho), rho = max(|duv/dx * size|, |duv/dy * size|)
// with size the base level's (width, height): the OpenGL scale-factor rule,
// so an anisotropic footprint takes its longer axis. Not clamped; -inf when
// the derivatives are zero (pure magnification).
float texture_lod(const Image& image, glm::vec2 duv_dx, glm::vec2 duv_dy);

// One texel of a mip level, integer coordinates already wrapped, as linear RGBA.
glm::vec4 fetch_texel(const Image& image, int level, int x, int y);

// Filtered lookup inside one mip level (no mip selection).
glm::vec4 sample_level(const Image& image, int level, glm::vec2 uv, Filter filter, Wrap wrap_s,
                       Wrap wrap_t);

// Lookup at a given level of detail (texture_lod's lambda): lookups of
// several images of one base size at one surface point share the LOD.
glm::vec4 sample_texture_at_lod(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda);

// Full lookup: LOD from the screen-space UV derivatives (UV units per pixel),
// clamped to the chain, then the sampler's filters. Returns linear RGBA; an
// image without levels reads as opaque white, the neutral factor.
glm::vec4 sample_texture(const Image& image, const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                         glm::vec2 duv_dy);

}  // namespace cr

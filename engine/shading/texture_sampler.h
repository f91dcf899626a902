#pragma once
// Texture lookups: an Image (RGBA8 mip chain) read through a glTF Sampler,
// following the OpenGL 4.6 rules (section 8.14): level of detail from the
// scale factor, magnification/minification filters, nearest or linear
// (trilinear) mip selection, and the three glTF wrap modes. Texels are read
// as stored (RGBA8) and decoded to linear as they are read (texel_decode.h:
// sRGB colour through a table, other channels code / 255), before filtering,
// as GPUs do.
#include <cstdint>

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

// Where a lookup at one UV and level of detail reads: up to two mip levels,
// each a 2x2 block of texels (one texel, four times, for nearest filtering)
// with its bilinear fractions, and the second level's weight. It depends only
// on the image's mip sizes and the sampler, so the lookups of several images
// of one size through one sampler (a material's textures, mostly) share it.
struct TextureFootprint {
  struct Level {
    int index = 0;         // mip level
    uint32_t texel[4]{};   // texel indices (y * width + x): (x0,y0) (x1,y0) (x0,y1) (x1,y1)
    float ax = 0.0f, ay = 0.0f;
  };
  Level level[2];
  int levels = 0;  // 0: the image has no levels (reads as opaque white)
  float t = 0.0f;  // weight of level[1] when levels == 2
};
TextureFootprint texture_footprint(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda);
// The filtered value of `image` (of the footprint's mip sizes) over the footprint.
glm::vec4 sample_footprint(const Image& image, const TextureFootprint& footprint);

// Lookup at a given level of detail (texture_lod's lambda): lookups of
// several images of one base size at one surface point share the LOD.
glm::vec4 sample_texture_at_lod(const Image& image, const Sampler& sampler, glm::vec2 uv, float lambda);

// Full lookup: LOD from the screen-space UV derivatives (UV units per pixel),
// clamped to the chain, then the sampler's filters. Returns linear RGBA; an
// image without levels reads as opaque white, the neutral factor.
glm::vec4 sample_texture(const Image& image, const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                         glm::vec2 duv_dy);

// One texture of several read at the same surface point.
struct TextureLookup {
  const Image* image = nullptr;
  const Sampler* sampler = nullptr;
};
// sample_texture of each lookup at one point: out[k] for lookups[k]. Images
// of one base size read through one sampler (a material's textures, mostly)
// share the footprint, computed once: the LOD's log2, the wrapping and the
// filter weights are a large part of a lookup.
void sample_textures(const TextureLookup* lookups, int count, glm::vec2 uv, glm::vec2 duv_dx, glm::vec2 duv_dy,
                     glm::vec4* out);

// The UVs and UV derivatives of several surface points (structure of arrays).
struct TexturePoints {
  static constexpr int kCapacity = 64;
  int count = 0;  // at most kCapacity
  const float *u, *v;           // TEXCOORD_0
  const float *du_dx, *dv_dx;   // UV change per pixel step in x
  const float *du_dy, *dv_dy;   // ... and in y
};
// sample_textures at every point, lookup by lookup: out[k * points.count + i]
// for lookups[k] at point i, the same floats. Each stage runs over all the
// points before the next (LODs, footprints, filtering), so the square roots
// and log2 calls of many points overlap instead of waiting one by one.
void sample_textures(const TextureLookup* lookups, int count, const TexturePoints& points, glm::vec4* out);

}  // namespace cr

#pragma once
// The per-pixel composite: sky (sky-view LUT + sun disk with limb darkening,
// attenuated by the transmittance LUT) where nothing was drawn, evaluated on a
// grid and interpolated where that is exact to 0.3%; aerial perspective
// (froxel LUT, trilinear; ray-marched beyond its range) on opaque pixels. In
// the space fallback the sky-view LUT is the one built for space and opaque
// pixels are ray marched.
#include <cstddef>
#include <span>

#include <glm/glm.hpp>

#include "atmosphere/sky_frame.h"
#include "engine/render/frame_buffers.h"

namespace cr {

// Sky radiance (cd/m^2) along a world direction, without / with the sun disk.
glm::vec3 sky_radiance(const SkyFrame& f, const glm::vec3& dir, bool with_sun_disk);
// sky_radiance(f, dir, false) for n directions (dx[i], dy[i], dz[i]) into out[i],
// bit for bit: the LUT coordinates of all of them come from one loop that vectorizes.
void sky_radiance_batch(const SkyFrame& f, size_t n, const float* dx, const float* dy, const float* dz,
                        glm::vec3* out);
// Applies aerial perspective to a surface colour seen at `distance` metres along `dir`.
glm::vec3 apply_aerial_perspective(const SkyFrame& f, const glm::vec3& dir, float distance, const glm::vec3& color);
// Radiance of the sun disk along dir (0 outside the disk), before the atmosphere.
glm::vec3 sun_disk_radiance(const SkyFrame& f, const glm::vec3& dir);

// Composites the rectangle [x0, x1) x [y0, y1) of the buffers in place.
void composite_sky(const SkyFrame& f, FrameBuffers& buffers, int x0, int y0, int x1, int y1);
// The same for edge-pixel fragments of a width x height frame, each along
// the ray through its own screen position, at its own distance (one at a
// time through sky_radiance and apply_aerial_perspective, the definitions
// the pixels' batched composite follows).
void composite_sky_fragments(const SkyFrame& f, int width, int height, std::span<EdgeFragment> fragments);

}  // namespace cr

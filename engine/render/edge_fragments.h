#pragma once
// From a multisampled visibility buffer to what the passes after it read:
// per pixel, the one surface all its samples see (id and depth, at the pixel
// centre: the pattern's offsets sum to zero, so the mean of the samples'
// depths is the plane's value there), or, at an edge pixel, one fragment per
// distinct surface or sky among its samples (FrameBuffers::fragments).
//
// A surface is a triangle together with the triangles of the same draw that
// continue its plane at the samples they cover (their depth within
// kSurfaceDepthTolerance of its plane's): the inner edges of a mesh are no
// edges, so a pixel there is shaded once, with the first sample's triangle,
// as a pixel inside one triangle is. Silhouettes, creases in depth and the
// boundaries between draws stay edges. (An orthographic view's planes carry
// no depth in the interpolation planes: there only equal triangles merge.)
#include <cstdint>
#include <vector>

#include "engine/core/job_system.h"
#include "engine/raster/tiled_rasterizer.h"
#include "engine/render/frame_buffers.h"
#include "engine/scene/camera.h"

namespace cr {

// Per-tile fragment lists, kept between frames so steady frames do not allocate.
using FragmentRows = std::vector<std::vector<EdgeFragment>>;

// An edge pixel's entry in the per-pixel ids: its first fragment's index
// with the top bit set (triangle ids never set it; kNoTriangle is not one).
inline uint32_t edge_pixel_id(uint32_t first_fragment) { return 0x80000000u | first_fragment; }
inline bool is_edge_pixel(uint32_t id) { return id != kNoTriangle && (id & 0x80000000u) != 0; }
inline uint32_t first_fragment(uint32_t edge_id) { return edge_id & 0x7FFFFFFFu; }

// ids/depth: per pixel (edge_pixel_id and the farthest fragment's depth at
// edge pixels); fragments: every edge pixel's, grouped by pixel (tile by
// tile, row-major within a tile), each pixel's in first-sample order,
// colour 0. Distances of the fragments from `cam` (view_distance.h).
// Deterministic for any thread count.
inline constexpr float kSurfaceDepthTolerance = 0.005f;  // relative, in view depth

void classify_samples(const TiledRasterizer& raster, const Camera& cam, JobSystem& jobs, std::vector<uint32_t>& ids,
                      std::vector<float>& depth, std::vector<EdgeFragment>& fragments, FragmentRows& rows);

// Boundaries of chunks of about `grain` fragments that start at a pixel's
// first fragment: [starts[c], starts[c + 1]) for c < starts.size() - 1.
std::vector<size_t> fragment_chunks(const std::vector<EdgeFragment>& fragments, size_t grain);

// Replaces each edge pixel's colour by its fragments' weighted sum (in their order).
void resolve_fragments(const std::vector<EdgeFragment>& fragments, std::vector<glm::vec3>& color, JobSystem& jobs);

}  // namespace cr

#pragma once
// A draw's material and the alpha-MASK coverage test the rasterizers run.
#include "engine/raster/tiled_rasterizer.h"
#include "engine/scene/scene.h"

namespace cr {

// The primitive's material, or glTF's default (white, metallic 1, roughness 1).
const Material& material_of(const Scene& scene, const Primitive& prim);
// Alpha-MASK coverage of a rasterizer's triangles: base-colour alpha >= cutoff.
CoverageFn alpha_coverage(const Scene& scene, const TiledRasterizer& raster);

}  // namespace cr

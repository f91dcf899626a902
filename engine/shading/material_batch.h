#pragma once
// Materials evaluated over a batch of surface points: per run of points
// sharing a material, its texture lookups together and its factors in
// vectorised loops field by field; the normal maps batch-wide in one
// vectorised loop.
#include "engine/scene/scene.h"
#include "engine/shading/shading_batch.h"
#include "engine/shading/surface_batch.h"

namespace cr {

// Fills `batch` with the finished surfaces' points, point k shaded with
// *materials[k]: what SurfaceShader::add appends for the surface at() gives
// (the same floats, tested), so that SurfaceShader::shade_batch lights them.
// `emissive_luminance`: cd/m^2 of emissive 1.0 (material_eval.h).
void evaluate_materials(const Scene& scene, const SurfaceBatch& surfaces, const Material* const* materials,
                        float emissive_luminance, ShadingBatch& batch);

}  // namespace cr

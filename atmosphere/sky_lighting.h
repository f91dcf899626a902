#pragma once
// Surface lighting from the atmosphere: the sun's illuminance at any world
// point through the transmittance LUT (planet shadow included), and the sky's
// radiance projected onto SH L2 for the ambient term.
#include <array>
#include <memory>

#include <glm/glm.hpp>

#include "atmosphere/sky_frame.h"
#include "engine/shading/light_environment.h"

namespace cr {

// Sky radiance (sun disk excluded) projected onto the engine's SH L2 basis
// (sh_project: a fixed quadrature, summed in a fixed order).
std::array<glm::vec3, 9> sky_ambient_sh(const SkyFrame& f);
// Fills sun direction, illuminance at the camera, sun_at, ambient_sh and the
// specular environment (sky_environment.h; null: the SH lights both lobes).
void fill_light_environment(const SkyFrame& f, LightEnvironment& light,
                            std::shared_ptr<const SpecularEnvironment> specular = nullptr);

}  // namespace cr

#pragma once
// The light a frame's surfaces receive: the sun and an ambient (sky) term,
// optionally with a prefiltered environment for glossy reflections.
// The engine fills it from the scene file; the plugin that provides the
// light environment (the atmosphere) rewrites it in a pass that writes
// EngineResources::light (engine/render/plugin.h).
#include <array>
#include <cstddef>
#include <functional>
#include <memory>

#include <glm/glm.hpp>

#include "engine/shading/specular_environment.h"

namespace cr {

struct LightEnvironment {
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};  // unit, world space, towards the sun
  glm::vec3 sun_illuminance{0.0f};            // RGB lux on a surface facing the sun
  // Optional per-point sun illuminance (e.g. attenuated by the atmosphere's
  // transmittance at the point's altitude): out[i] for world_pos[i], i < n.
  // Called with many points at once so that shading pays one indirect call per
  // batch, not per pixel. When empty, sun_illuminance is used.
  std::function<void(const glm::vec3* world_pos, glm::vec3* out, size_t n)> sun_at;
  // Incoming ambient radiance as real SH L2 coefficients (cd/m^2):
  // L(w) = sum_i ambient_sh[i] * Y_i(w), order Y00, Y1-1, Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22.
  std::array<glm::vec3, 9> ambient_sh{};
  // Optional prefiltered environment for the specular ambient (glossy
  // reflections). Null: the specular ambient is ambient_sh's radiance in the
  // mirror direction, so the scene's ambient lights both lobes. Shared: the
  // plugin that publishes it may build the next one while frames shade.
  std::shared_ptr<const SpecularEnvironment> specular;
};

// The sun's illuminance at one world point: sun_at when set, else sun_illuminance.
inline glm::vec3 sun_illuminance_at(const LightEnvironment& light, const glm::vec3& world_pos) {
  if (!light.sun_at) return light.sun_illuminance;
  glm::vec3 e;
  light.sun_at(&world_pos, &e, 1);
  return e;
}

}  // namespace cr

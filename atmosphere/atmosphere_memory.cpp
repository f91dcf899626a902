#include "atmosphere/atmosphere_memory.h"

#include "atmosphere/aerial_perspective_lut.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/skyview_lut.h"

namespace cr {

namespace {

// Each LUT is held twice: the published one and the rebuild in progress.
constexpr size_t kCopies = 2;
constexpr size_t kRgb = sizeof(glm::vec3), kRgbPad = 4 * sizeof(float);

std::string dims(int w, int h, int d = 1) {
  std::string s = std::to_string(w) + 'x' + std::to_string(h);
  if (d > 1) s += 'x' + std::to_string(d);
  return s;
}

}  // namespace

void estimate_atmosphere_memory(const AtmosphereSettings& s, const std::string& file, MemoryBudget& memory) {
  auto texels = [](int w, int h, int d = 1) { return saturating_product({size_t(w), size_t(h), size_t(d)}); };
  // Transmittance: the image and its padded copy for vector loads.
  memory.charge("transmittance LUT " + dims(s.transmittance_width, s.transmittance_height), file,
                "atmosphere.transmittance_lut.width",
                saturating_product({texels(s.transmittance_width, s.transmittance_height), kCopies * (kRgb + kRgbPad)}));
  // Multiscattering: image, padded copy, the moment images (plain and
  // padded), the clamp mask and f_ms, and one field per explicit order.
  const size_t ms_texel = kRgb + kRgbPad + kMsMomentCount * (kRgb + kRgbPad) + 1 + kRgb +
                          size_t(s.multiscattering_max_explicit_orders + 1) * kRgbPad;
  memory.charge("multiscattering LUT " + dims(s.multiscattering_width, s.multiscattering_height), file,
                "atmosphere.multiscattering_lut.width",
                saturating_product({texels(s.multiscattering_width, s.multiscattering_height), kCopies * ms_texel}));
  // Its march of one altitude row: every direction's steps, about 18 floats
  // each (MarchStep and the per-step lookups), on each of up to 64 workers.
  memory.charge("multiscattering march of " + std::to_string(s.multiscattering_directions) + " directions x " +
                    std::to_string(s.multiscattering_steps) + " steps",
                file, "atmosphere.multiscattering_lut.directions",
                saturating_product({size_t(s.multiscattering_directions) / 2, size_t(s.multiscattering_steps),
                                    18 * sizeof(float), 64}));
  memory.charge("sky-view LUT " + dims(s.skyview_width, s.skyview_height), file, "atmosphere.skyview_lut.width",
                saturating_product({texels(s.skyview_width, s.skyview_height), kCopies * (2 * kRgb + sizeof(SkyViewTexel))}));
  // Aerial perspective: luminance and transmittance images and the packed
  // froxels, which carry one more texel along x and y for the lookups.
  memory.charge("aerial-perspective LUT " + dims(s.ap_width, s.ap_height, s.ap_depth), file,
                "atmosphere.aerial_perspective_lut.width",
                saturating_product({kCopies, texels(s.ap_width, s.ap_height, s.ap_depth) * 2 * kRgb +
                                                 texels(s.ap_width + 1, s.ap_height + 1, s.ap_depth) *
                                                     sizeof(FroxelTexel)}));
  // Environment: the published levels, the rebuild's and its box pyramid
  // (each under 4/3 of level 0), padded RGB.
  const size_t level0 = texels(s.environment_size, s.environment_size);
  memory.charge("specular environment " + dims(s.environment_size, s.environment_size), file,
                "atmosphere.environment.size", saturating_product({level0 * 4 / 3, 3 * kRgbPad}));
}

}  // namespace cr

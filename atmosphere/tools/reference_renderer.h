#pragma once
// The ground truth: no LUTs, double precision, per pixel.
//  - single scattering (and the sunlit ground seen directly) by a deterministic
//    nested ray march with altitude-adaptive steps (~300 m near the ground);
//  - all higher orders by a Monte-Carlo volumetric path tracer: free-flight
//    sampling with one-sample spectral MIS over the three channels, phase
//    sampling (Henyey-Greenstein mixture), Lambertian ground bounces with the
//    albedo, next-event estimation of the sun at every vertex after the first
//    (the first is the single-scattering term), Russian roulette.
// Across the spectrum (ReferenceSettings::sampling, spectral_sampling.h) the
// wavelengths run in groups of three, each group with the model moved to its
// wavelengths (model_spectrum.h):
//  - the single-scattering march integrates the column densities (Rayleigh,
//    Mie, ozone: independent of wavelength) along the view ray and the nested
//    sun rays once, and turns them into every group's optical depths;
//  - each path of the path tracer carries one group of three wavelengths (hero
//    wavelengths; the spectral MIS over its three channels is the
//    hero-wavelength MIS): path k of a pixel takes group (k + a per-pixel
//    offset) mod G, weighted by G. The paths' groups interleave the sampling's
//    wavelengths (group g: wavelengths g, g + G, g + 2G), so each path spans
//    the spectrum.
// The groups' radiance for a unit sun at every wavelength is combined into
// linear sRGB with the sampling's weights, then scaled by sun_illuminance.
// It runs as jobs (one pixel per element, a fixed seed per pixel: identical
// for any thread count) and reports progress.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/spectral_sampling.h"
#include "engine/core/job_system.h"

namespace cr {

struct ReferenceSettings {
  int samples_per_pixel = 64;  // paths for orders >= 2
  int max_bounces = 64;
  uint64_t seed = 1;
  bool single_scattering = true;
  bool multiple_scattering = true;
  // The wavelengths and their sRGB weights: rgb_sampling() is the model's own
  // three channels; reference_sampling() the full-spectral reference (47 bands).
  SpectralSampling sampling = rgb_sampling();
};

struct ReferenceView {
  glm::dvec3 origin{0.0};                 // planet-centred camera position
  std::vector<glm::vec3> directions;      // one unit world direction per pixel
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};
  glm::vec3 sun_illuminance{110000.0f};
};

struct ReferenceImage {
  std::vector<glm::vec3> radiance;  // cd/m^2 per pixel
  std::vector<float> noise;         // standard error of the luminance (Monte-Carlo part) per pixel
  // Relative standard errors of the pixel's r/g and b/g (first-order, from the
  // paths' channel variances and covariances): a full-spectral path's colour is
  // far noisier than its luminance (the sRGB weights of a band are partly negative).
  std::vector<glm::vec2> ratio_noise;
};

// `progress(done, total)` is called from job threads after each chunk of 64 pixels (may be empty).
ReferenceImage render_reference(const AtmosphereModel& model, const ReferenceView& view,
                                const ReferenceSettings& settings, JobSystem& jobs,
                                const std::function<void(size_t, size_t)>& progress);

// Transmittance from a planet-centred point to the top of the atmosphere
// towards `dir` (0 when the planet blocks it; no sun-disk penumbra), by the
// reference's adaptive march. For tests.
glm::dvec3 reference_transmittance(const AtmosphereModel& model, const glm::dvec3& point, const glm::dvec3& dir);

}  // namespace cr

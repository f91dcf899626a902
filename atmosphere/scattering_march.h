#pragma once
// The single-scattering ray march shared by the sky-view, aerial-perspective
// and space-fallback paths, split in two halves: march() does everything that
// depends only on the ray (medium, throughput, per-step weights with the
// analytic segment integral (S - S*T)/sigma_t), and shade() adds what depends
// on the sun (sun transmittance, phases, the multiple-scattering LUT). A row of
// the sky-view LUT marches once and shades every longitude.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/multiscattering_lut.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

struct AtmosphereLuts {
  const AtmosphereModel& model;
  const TransmittanceLut& transmittance;
  const MultiScatteringLut& multiscattering;
};

struct MarchSample {
  float t;          // distance from the ray start
  float inv_r;      // 1 / radius at the sample
  TransmittanceRow row;
  float ms_y;       // multiple-scattering LUT row coordinate
  glm::vec3 w_rayleigh;  // throughput * rayleigh scattering * segment integral
  glm::vec3 w_mie;
  glm::vec3 w_ms;        // throughput * total scattering * segment integral
};

struct MarchedRay {
  float r0 = 0.0f;
  float r0_mu = 0.0f;  // r0 * the zenith cosine of the ray at its start
  std::vector<MarchSample> samples;
  glm::vec3 transmittance{1.0f};  // over the whole marched length
  bool hits_ground = false;
  float ground_t = 0.0f;
  TransmittanceRow ground_row{};
  float ground_ms_y = 0.0f;
};

enum class StepSpacing { Uniform, Quadratic };

// The ray-only quantities of many march steps, one array per quantity: the
// caller sets the step centres t and lengths dt (any spacing), march_media()
// fills the rest in one loop that vectorizes, and accumulate() turns a run of
// steps into a MarchedRay. march() is these three; the aerial-perspective LUT
// marches a whole froxel column at once and shades it slice by slice
// (shade_runs, froxel_column.h).
struct MarchSteps {
  std::vector<float> t, dt;
  std::vector<float> h;                       // altitude (floored)
  std::vector<float> rayleigh, mie;           // densities
  std::vector<float> step_t[3], segment[3];   // per channel: exp(-tau), (1 - exp(-tau)) / sigma_t
  void resize(size_t n);
};
void march_media(const AtmosphereModel& m, float h0, float mu, float floor_altitude, MarchSteps& steps);
// The samples of steps [begin, end) as a ray starting at altitude h0 with zenith cosine mu, its
// throughput from 1 at `begin`.
void accumulate(const AtmosphereLuts& luts, const MarchSteps& steps, size_t begin, size_t end, float h0, float mu,
                MarchedRay& out);

// Marches [t_begin, t_end] along the ray from altitude h0 with zenith cosine mu.
// `hits_ground` is set when t_end is the ground hit (ground shading in shade()).
// `floor_altitude` pushes samples that fall under it up to it (froxels below the ground).
void march(const AtmosphereLuts& luts, float h0, float mu, float t_begin, float t_end, int steps,
           StepSpacing spacing, bool ends_on_ground, float floor_altitude, MarchedRay& out);

// In-scattered luminance of a marched ray for unit sun illuminance, split into
// the Mie single scattering without its phase (the phase is constant along the
// ray: a caller may apply it per pixel, where a sharp forward lobe needs more
// resolution than a LUT has) and everything else. mu_s is the sun zenith cosine
// at the ray start, nu the cosine between ray and sun.
struct ShadedRay {
  glm::vec3 rest{0.0f};          // Rayleigh single scattering, multiple scattering, ground
  glm::vec3 mie_unphased{0.0f};  // Mie single scattering / phase(nu)
  glm::vec3 total(float mie_phase_value) const { return rest + mie_unphased * mie_phase_value; }
};
ShadedRay shade_split(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu);
// shade_split for n directions sharing one marched ray (a sky-view row: one
// ray per view zenith, many angles to the sun), nu[j] each, into out[j]. The
// results are bit-identical to shade_split's; the lookup coordinates of all
// directions at a step come from one loop that vectorizes.
void shade_split_many(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, size_t n, const float* nu,
                      ShadedRay* out);
glm::vec3 shade(const AtmosphereLuts& luts, const MarchedRay& ray, float mu_s, float nu);

// Whole-ray helper: from altitude h0 (clamped into the atmosphere by moving the
// start to the top when above it) along mu up to `max_distance` (or the ground/top).
// Returns the luminance for unit sun illuminance and the transmittance.
struct RayScattering {
  glm::vec3 luminance{0.0f};
  glm::vec3 transmittance{1.0f};
  bool hits_ground = false;
};
RayScattering integrate_ray(const AtmosphereLuts& luts, double r, double mu, double mu_s, double nu,
                            double max_distance, int min_steps, int max_steps, MarchedRay& scratch);

// Step count for a ray of `length` metres: min_steps at 0 growing to max_steps at 100 km.
int variable_steps(float length, int min_steps, int max_steps);

}  // namespace cr

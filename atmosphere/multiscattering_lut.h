#pragma once
// LUT 2: Hillaire's multiple-scattering term Psi_ms over (sun zenith cosine,
// altitude), with three changes that matter in twilight and near the ground.
// Per texel, `directions` rays are marched (sqrt(directions) polar bands,
// denser near the local horizon; ground bounce with the albedo) to get the
// second-order luminance L2 (its sphere mean and moments) and the transfer
// factor f_ms, which includes the ground reflecting the isotropic field back.
//  1. The sun's light scatters into each direction with the true phase
//     (Hillaire: isotropic), and L2's directional moments are kept for the
//     scattering towards the viewer (MsMoment below).
//  2. `explicit_orders` further orders are marched, each from the previous
//     order's field at every step's own altitude and sun angle (Hillaire's
//     series assumes they are as dark as the texel's own, which in Earth's
//     shadow they are not); the geometric series 1 / (1 - f_ms) covers the
//     rest from the last one. How many an atmosphere needs depends on f_ms:
//     see explicit_orders_for().
//  3. The ground lit by the once-scattered sky reflects it (f_ms has the
//     ground reflect only what the medium scatters onto it).
// The bake runs in passes(): pass 0 the second order, pass p the order p + 2;
// a pass needs all of the previous one. f_ms is clamped to max_fms (dense
// atmospheres drive it to 1) and clamped texels are counted. The sun zenith
// axis is non-linear (MultiScatteringMapping), altitude is linear.
#include <cstddef>
#include <cstdint>
#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/atmosphere_model.h"
#include "atmosphere/float4.h"
#include "atmosphere/lut_image.h"
#include "atmosphere/transmittance_lut.h"

namespace cr {

class JobSystem;

struct AltitudeMarch;

// The sun zenith cosine axis, mu_s in [-1, 1] <-> unit x in [0, 1], in three
// linear pieces. Below mu_s ~ 0 Psi falls exponentially into Earth's shadow (an
// e-fold per ~0.02 of mu_s near the ground): linear interpolation between
// uniform columns 0.065 apart overestimated it 2-4x there, which is where the
// sky of a sun below the horizon samples it. Above mu_s ~ 0.1 Psi is
// nearly linear and below -0.3 it is ~0, so [-0.3, 0.1] gets 18/31 of the axis
// (18 of a 32-wide LUT's 31 intervals), [0.1, 1] 11/31 and [-1, -0.3] 2/31.
struct MultiScatteringMapping {
  static constexpr float kShadowMu = -0.3f;  // the dense piece's ends
  static constexpr float kLitMu = 0.1f;
  static constexpr float kShadowUnit = 2.0f / 31.0f;  // and their unit x
  static constexpr float kLitUnit = 20.0f / 31.0f;

  // Selects, no division: inlined into the march's lookup loops, it vectorizes.
  static float to_unit(float mu_s) {
    constexpr float below = kShadowUnit / (kShadowMu + 1.0f);
    constexpr float dense = (kLitUnit - kShadowUnit) / (kLitMu - kShadowMu);
    constexpr float above = (1.0f - kLitUnit) / (1.0f - kLitMu);
    const float low = (mu_s + 1.0f) * below;
    const float mid = kShadowUnit + (mu_s - kShadowMu) * dense;
    const float high = kLitUnit + (mu_s - kLitMu) * above;
    return mu_s < kShadowMu ? low : (mu_s < kLitMu ? mid : high);
  }
  static float from_unit(float unit) {
    if (unit < kShadowUnit) return -1.0f + unit / kShadowUnit * (kShadowMu + 1.0f);
    if (unit < kLitUnit) return kShadowMu + (unit - kShadowUnit) / (kLitUnit - kShadowUnit) * (kLitMu - kShadowMu);
    return kLitMu + (unit - kLitUnit) / (1.0f - kLitUnit) * (1.0f - kLitMu);
  }
};

// The directional part of the second-order field, kept beside Psi_ms so that
// the scattering towards the viewer can use the phase of its angle (Hillaire's
// LUT is isotropic there). Moments of the luminance L(omega) arriving at the
// texel's point, in the frame x = towards the sun horizontally, y = up (the
// field is mirror-symmetric about the sun plane, so no z terms): the traceless
// second moment (3 omega omega^T - I; its zz = -xx - yy) and the first moment.
// A phase of Legendre coefficients k_l adds to the isotropic Psi
//   k_1 * 3 F.v + k_2 * 10 / 4 * v^T A v    (v: the view direction, A, F: the
// moments as sphere means), which for Rayleigh (k_1 = 0, k_2 = 1/10) is v^T A v / 4.
enum MsMoment { kMsQuadXX, kMsQuadYY, kMsQuadXY, kMsFirstX, kMsFirstY, kMsMomentCount };

// The explicit orders an atmosphere needs: the fewest k in [min_orders,
// max_orders] for which the series' share f^(k+1) is at most tail_share, f
// being the largest f_ms of a LUT of `height` altitude rows (the bake's own
// march of each row, without the transmittance LUT: f_ms does not depend on
// the sun), clamped to max_fms. The series is least accurate where it
// carries most (dense air: f near 1), while thin air needs none; tail_share
// 1 gives min_orders.
struct ExplicitOrderChoice {
  float max_fms = 0.0f;  // f (largest channel and row)
  int orders = 0;
  bool capped = false;  // max_orders reached with the series' share still above tail_share
};
ExplicitOrderChoice explicit_orders_for(const AtmosphereModel& model, int height, int directions, int steps,
                                        float max_fms, int min_orders, int max_orders, float tail_share);

class MultiScatteringLut {
 public:
  MultiScatteringLut() = default;
  MultiScatteringLut(const AtmosphereModel& model, int width, int height, int directions, int steps, float max_fms,
                     int explicit_orders);

  // Work items [begin, end): item = pass * texel_count() + texel (row-major:
  // x = sun zenith, y = altitude). Items of pass p may run only once all of
  // pass p - 1 have: bake in order, or split parallel work at pass ends.
  void bake(size_t begin, size_t end, const TransmittanceLut& transmittance);
  size_t texel_count() const { return image_.count(); }
  int passes() const { return int(fields_.size()); }
  int explicit_orders() const { return explicit_orders_; }
  size_t work_items() const { return texel_count() * size_t(passes()); }

  // Psi_ms for unit sun illuminance: in-scattered luminance per unit scattering coefficient.
  glm::vec3 sample(float altitude, float mu_s) const {
    return sample_bilinear(image_, MultiScatteringMapping::to_unit(mu_s) * float(image_.width - 1),
                           altitude * inv_top_altitude_ * float(image_.height - 1));
  }
  // The second order alone (pass 0's field L2: sphere-mean luminance), for tests.
  glm::vec3 second_order(float altitude, float mu_s) const;
  int clamped_texels() const;  // texels whose f_ms hit max_fms
  float max_fms_seen() const;  // largest unclamped f_ms component over the LUT

  // Rounds the image to q15 (one scale) for "luts": "q15". The moments
  // (signed, small corrections to the image) stay float.
  void quantize_q15();
  // Psi and its moments from the LUTs of a spectral sampling's groups
  // (spectral_mix.h), built with the same arguments: Psi clipped at 0, the
  // signed moments not; a texel counts as clamped if any group's was.
  void mix_from(const std::vector<const MultiScatteringLut*>& groups, const SpectralSampling& sampling,
                JobSystem& jobs);

  const LutImage& image() const { return image_; }
  const float* packed() const { return packed_.data(); }  // the image as rgb + pad (see float4.h)
  // Moment k's plane, rgb + pad like packed(), pre-scaled: Rayleigh's quadratic
  // term, and Mie's first-order term (k_1 * 3).
  const float* moment(int k) const { return moments_.data() + size_t(k) * 4 * image_.count(); }
  const LutImage& moment_image(int k) const { return moment_images_[size_t(k)]; }  // the same as images
  // Mie's quadratic term over Rayleigh's (10 k_2 of the Mie phase).
  float mie_quadratic_ratio() const { return mie_quadratic_ratio_; }

 private:
  void bake_second_order(const AltitudeMarch& am, const TransmittanceLut& transmittance, size_t i, float mu_s,
                         bool ground_row);
  void bake_higher_order(const AltitudeMarch& am, int pass, size_t i, float mu_s);
  glm::vec3 march_field(const AltitudeMarch& am, const float* previous, float mu_s) const;
  void add_field_rows(AltitudeMarch& am) const;
  LutCoord field_row(float altitude) const;  // a field's altitude coordinate
  glm::vec3 ground_skylight(const AltitudeMarch& am, float mu_s) const;
  glm::vec3 ground_sky(float mu) const;  // ground_sky_ at a sun cosine
  // A field_ (rgb + pad texels) at an altitude and sun cosine, bilinear, clamped to the LUT.
  Float4 sample_field(const float* field, float altitude, float mu) const;

  AtmosphereModel model_;
  int directions_ = 64;
  int steps_ = 20;
  float max_fms_ = 0.95f;
  int explicit_orders_ = 1;
  float inv_top_altitude_ = 0.0f;
  LutImage image_;
  std::vector<float> packed_;
  std::array<LutImage, kMsMomentCount> moment_images_;
  std::vector<float> moments_;  // kMsMomentCount planes of rgb + pad texels
  std::array<float, kMsMomentCount> moment_scale_{};
  float mie_quadratic_ratio_ = 0.0f;
  std::vector<uint8_t> clamped_;
  std::vector<float> fms_;
  std::vector<std::vector<float>> fields_;  // per pass, its order's field (sphere mean), rgb + pad texels
  std::vector<glm::vec3> transfer_;         // f_ms, clamped
  std::vector<glm::vec3> ground_sky_;       // per sun column: the ground's irradiance from the once-scattered sky
  glm::vec3 ground_irradiance_{0.0f};  // of the ground from a unit isotropic field: its share of f_ms
};

}  // namespace cr

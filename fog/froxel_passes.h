#pragma once
// The froxel fog passes as functions of explicit inputs (the plugin chains
// them in the frame graph; tests call them directly). Every pass splits its
// output by column rows or slices over the job system: each froxel is written
// by exactly one job, so results are identical for any thread count.
//
// Data per froxel (column-major, see FroxelGrid):
//   density    FogDensity: scattering RGB and extinction at the froxel centre
//   sun        the sun's shadow visibility at an importance-sampled point of
//              the froxel (no illuminance, no phase function): float, or q15
//              codes with "precision": "fixed" (sun_term_format.h); the
//              passes that carry it have an overload for each
//   volume     IntegratedFroxel: in-scattered radiance and transmittance from
//              the near plane to the froxel's far boundary, and its extinction
//              (fixed point: FixedIntegratedFroxel, fixed_volume.h)
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"
#include "engine/render/frame_buffers.h"
#include "engine/scene/camera.h"
#include "engine/shading/light_environment.h"
#include "fog/fixed_volume.h"
#include "fog/fog_medium.h"
#include "fog/froxel_grid.h"
#include "fog/volume_shadow.h"

namespace cr {

// The grid placed in one frame's view: column centre directions and how many
// slices of each column are worked on (all of them unless depth-culled).
//   active_slices  slices filter and integration produce: the composite reads
//                  nothing beyond them
//   lit_slices     slices density, lighting and reprojection produce: active
//                  dilated by one column, so the 3x3 filter of an active
//                  froxel reads only lit neighbours
struct FroxelView {
  FroxelGrid grid;
  Camera camera;
  std::vector<glm::vec3> directions;  // per column, unit, world space
  std::vector<uint16_t> active_slices, lit_slices;  // per column
};
FroxelView make_froxel_view(const FroxelGrid& grid, const Camera& camera, JobSystem& jobs);

// Depth-aware culling (UE/HDRP keep a max depth per tile): a froxel behind the
// farthest opaque surface of the pixels that can read it is invisible. A pixel
// reads the slices up to its distance in the 2x2 columns around it, all within
// the 3x3 columns around its own tile, so a column's active slices are those
// up to the farthest pixel (sky: the last slice) of the 3x3 tiles around it.
// `distance` is the frame's per-pixel distance (metres, +inf for sky).
void cull_froxels_by_depth(FroxelView& view, const std::vector<float>& distance, JobSystem& jobs);

// Screen rectangle (columns) and slice range a volume may overlap (the box
// clipped where the grid's nearest points lie, so a box reaching behind the
// camera still has a bounded one); volumes outside the view or the fog range
// get none and cost nothing.
struct VolumeFootprint {
  int volume = 0;  // index into FogMedium::volumes()
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive column ranges
  int k0 = 0, k1 = -1;                   // inclusive slice range
};
std::vector<VolumeFootprint> volume_footprints(const FroxelView& view, const FogMedium& medium);

struct VoxelizeStats {
  int visible_volumes = 0;
  size_t volume_froxels = 0;  // froxels whose footprint a volume covers
};
// fog.density: height fog in every lit froxel, then each visible volume in its
// footprint (lit froxels only). In steps: the frame's plan (footprints, slice
// centres), then any rows of columns (the plugin voxelises each row right
// before lighting it, while the row is in cache; see light_froxels).
//
// Where a volume reaches a froxel, it takes the mean of the whole blend
// (height fog, then every volume in file order) at `samples` stratified
// points along the slice: volume edges, fades and noise are finer than a
// slice (1-2 m deep at 20-40 m), so one point per slice aliases them, and
// history cannot recover detail that was never sampled. The mean density
// gives the slice's exact optical depth along the column's centre ray.
// Elsewhere the height fog is smooth and one centre point suffices: a froxel
// none of whose points lies in a volume keeps it, so the footprints only
// bound the work and never change a value.
struct DensityPlan {
  std::vector<VolumeFootprint> footprints;
  std::vector<float> centers;  // per slice: its centre distance
  int samples = 1;             // points per slice where volumes lie
  std::vector<float> sample_t; // per slice, `samples` stratified distances
  VoxelizeStats stats;
};
DensityPlan plan_density(const FroxelView& view, const FogMedium& medium, int samples);
// Rows [y0, y1) of `density` (sized to the grid by the caller).
void voxelize_rows(const FroxelView& view, const FogMedium& medium, const DensityPlan& plan, int y0, int y1,
                   std::vector<FogDensity>& density);
// All rows, in parallel.
VoxelizeStats voxelize_density(const FroxelView& view, const FogMedium& medium, int samples, JobSystem& jobs,
                               std::vector<FogDensity>& density);

struct JitterInputs {
  bool enabled = true;
  int frame = 0;    // index into the 7-frame sequence
  int samples = 1;  // > 1: average this many consecutive sequence samples (non-temporal reference)
};
// fog.lighting: the sun's shadow visibility at the importance-sampled
// jittered point, for lit froxels with scattering (clear air gets 0: nothing
// multiplies it). before_rows (optional) runs on each job's rows [y0, y1)
// before they are lit: the voxelisation, so the density the lighting reads
// is still in cache.
//
// With `previous` (last frame's shadow map, under a sun that has moved since)
// and `light_change`, each sample is also looked up in the previous map, and
// light_change gets |visibility now - visibility then| at the same point (the
// temporal gradient of A-SVGF, exact where it is measured: the same point,
// two lights): how much the light itself changed there, which no
// reprojection of the history can account for. 0 in clear air.
//
// With `settled` (a still view, see settled_froxels.h), each column lights
// only the slices of its span and takes the settled samples elsewhere; it is
// ignored with `previous` (a moving sun lights everything).
//
// The q15 overload evaluates the same floats and stores each froxel's
// visibility and light change rounded to q15 (the settled samples are codes).
struct SliceSpan {  // slices [first, end) of a column
  uint16_t first = 0, end = 0;
};
template <class Value>
struct SettledSamples {
  const std::vector<SliceSpan>* spans = nullptr;  // per column: the slices to light
  const std::vector<Value>* values = nullptr;     // the sample of every other lit slice
};
void light_froxels(const FroxelView& view, const std::vector<FogDensity>& density, const VolumeShadow& shadow,
                   const JitterInputs& jitter, JobSystem& jobs, std::vector<float>& sun_visibility,
                   const std::function<void(int y0, int y1)>& before_rows = nullptr,
                   const VolumeShadow* previous = nullptr, std::vector<float>* light_change = nullptr,
                   const SettledSamples<float>* settled = nullptr);
void light_froxels(const FroxelView& view, const std::vector<FogDensity>& density, const VolumeShadow& shadow,
                   const JitterInputs& jitter, JobSystem& jobs, std::vector<uint16_t>& sun_visibility,
                   const std::function<void(int y0, int y1)>& before_rows = nullptr,
                   const VolumeShadow* previous = nullptr, std::vector<uint16_t>* light_change = nullptr,
                   const SettledSamples<uint16_t>* settled = nullptr);

// The same camera and grid layout: history is read in place.
bool same_view(const FroxelView& a, const FroxelView& b);

// fog.reproject: out = lerp(current, history(reprojected centre), weight);
// history is rejected outside the previous grid (frustum and depth range) or
// where it reads a froxel the previous frame culled, and, with clamp, limited
// to the current 3x3 neighbourhood's range in the slice (lit neighbours only).
// Produces the lit slices of each column. With light_change (see
// light_froxels) a froxel's history weight is history_weight * (1 - the
// largest change in its 3x3 neighbourhood in the slice): where a moving sun
// changed the visibility, history is dropped in proportion (a one-point
// measure misses most of a froxel, its neighbours' see the edge coming).
// The q15 overload blends by q15 lerps at q15 weights (the trilinear read's
// too); light change c scales the history share by (32768 - c) / 32768.
struct ReprojectStats {
  bool identity = false;       // same camera: history read in place
  size_t reads = 0;            // froxels whose history was looked up (with the clamp, those whose range is not one value)
  size_t rejected = 0;         // of those, the ones without history
  size_t clamped = 0;          // of those, the ones whose history lay outside the 3x3 range (the clamp cut it)
};
ReprojectStats reproject_history(const FroxelView& view, const std::vector<float>& current,
                                 const FroxelView& history_view, const std::vector<float>& history,
                                 float history_weight, bool clamp, JobSystem& jobs, std::vector<float>& out,
                                 const std::vector<float>* light_change = nullptr);
ReprojectStats reproject_history(const FroxelView& view, const std::vector<uint16_t>& current,
                                 const FroxelView& history_view, const std::vector<uint16_t>& history,
                                 float history_weight, bool clamp, JobSystem& jobs, std::vector<uint16_t>& out,
                                 const std::vector<uint16_t>* light_change = nullptr);

// fog.filter: 3x3 Gaussian (sigma 1 froxel) in each slice, separable, clamped
// at the edges; produces the active slices of each column. The q15 overload
// weighs each tap by integer weights summing to 32768 and rounds half up.
void filter_slices(const FroxelView& view, const std::vector<float>& in, JobSystem& jobs, std::vector<float>& scratch,
                   std::vector<float>& out);
void filter_slices(const FroxelView& view, const std::vector<uint16_t>& in, JobSystem& jobs,
                   std::vector<uint16_t>& scratch, std::vector<uint16_t>& out);

struct IntegratedFroxel {
  glm::vec3 in_scatter{0.0f};  // radiance added between the near plane and the far boundary
  float transmittance = 1.0f;  // from the near plane to the far boundary
  float extinction = 0.0f;     // of this froxel, for the exact in-slice lookup
};
struct MediumLighting {
  FogPhase phase = FogPhase::HenyeyGreenstein;
  float anisotropy = 0.0f;
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};
  glm::vec3 sun_illuminance{0.0f};
  const LightEnvironment* light = nullptr;  // per-point illuminance (sun_at) when set
  glm::dvec3 camera_position{0.0};
  std::array<glm::vec3, 9> ambient_sh{};
};
// The same values. `light` is not read: it is borrowed for one frame, and
// its sun_at, a function, is compared through its results (sun_knots, empty
// without sun_at) by the caller.
inline bool same_medium_lighting(const MediumLighting& a, const MediumLighting& b) {
  return a.phase == b.phase && a.anisotropy == b.anisotropy && a.sun_direction == b.sun_direction &&
         a.sun_illuminance == b.sun_illuminance && a.camera_position == b.camera_position &&
         a.ambient_sh == b.ambient_sh;
}
// The sun's illuminance where integration takes it: it varies slowly (the
// atmosphere's transmittance with altitude), so per row of columns sun_at
// runs at every kSunStride-th column (and the last), at the first and last
// slice centres: sun_knots_per_row knots of 2 values, row after row. Empty
// without sun_at (the illuminance is then the same everywhere).
constexpr int kSunStride = 8;
constexpr int sun_knots_per_row(int nx) { return (nx - 1) / kSunStride + 2; }
std::vector<glm::vec3> sun_knots(const FroxelView& view, const MediumLighting& lighting, JobSystem& jobs);
// fog.integrate: front-to-back per column over its active slices. The phase
// function and the sun's illuminance (lerped between the knots) are applied
// here at the column's centre direction (never jittered, never reprojected).
//
// Incremental integration: with `previous` (the visibility `volume` was last
// integrated from) and `continue_volume` (volume holds that integration, of
// this view, density and light), a column's slices before its first
// visibility that differs from previous, bit for bit, keep their volume,
// and the recurrence continues from there: the same bits as integrating
// all of it. previous is brought up to date either way. Returns how many
// froxels were integrated.
//
// The fixed-point overload (q15 visibility, FixedIntegratedFroxel: see
// fixed_volume.h and integration.cpp) keeps a column whose visibility is
// unchanged and integrates a changed one whole.
template <class Visibility>
struct IncrementalIntegration {
  std::vector<Visibility>* previous = nullptr;
  bool continue_volume = false;
};
size_t integrate_columns(const FroxelView& view, const std::vector<FogDensity>& density,
                         const std::vector<float>& sun_visibility, const MediumLighting& lighting,
                         const std::vector<glm::vec3>& knots, JobSystem& jobs, std::vector<IntegratedFroxel>& volume,
                         const IncrementalIntegration<float>& incremental = {});
size_t integrate_columns(const FroxelView& view, const std::vector<FogDensity>& density,
                         const std::vector<uint16_t>& sun_visibility, const MediumLighting& lighting,
                         const std::vector<glm::vec3>& knots, JobSystem& jobs,
                         std::vector<FixedIntegratedFroxel>& volume,
                         const IncrementalIntegration<uint16_t>& incremental = {});

// Composite of pixels [x0,x1) x [y0,y1): colour = colour * T + L at the
// pixel's distance. Bilinear across columns; along depth the froxel's
// homogeneous-medium closed form, so nothing behind the pixel's surface is
// added (no leak through opaque geometry). Sky (+inf) uses the far end.
// The fixed-point volume's froxels are decoded as they are read (radiance
// from hdr16, transmittance exp2_neg_q15 of the depth code, extinction from
// the depth codes' difference) and take the same float closed form.
void composite_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1);
void composite_fog(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                   const std::vector<float>& distance, std::vector<glm::vec3>& color, int width, int x0, int y0,
                   int x1, int y1);
// The same for edge-pixel fragments, each at its own screen position and distance.
void composite_fog_fragments(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume,
                             std::span<EdgeFragment> fragments);
void composite_fog_fragments(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                             std::span<EdgeFragment> fragments);
// The lookup itself: in-scattered radiance and transmittance at a pixel position and distance.
void lookup_fog(const FroxelGrid& grid, const std::vector<IntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance);
void lookup_fog(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume, float px, float py,
                float distance, glm::vec3& in_scatter, float& transmittance);
// A fixed-point froxel as the float record the composite reads: index's
// radiance and transmittance, and its slice's extinction.
IntegratedFroxel decode_froxel(const FroxelGrid& grid, const std::vector<FixedIntegratedFroxel>& volume,
                               size_t index);

}  // namespace cr

#pragma once
// Dynamic resolution's upscale: a frame rendered at the profile's internal
// size (render_scale) becomes the output size before the display transform.
//
// Linear colour goes through a separable Catmull-Rom filter (bicubic,
// B = 0, C = 0.5): sharper than bilinear and it reproduces linear gradients
// exactly, but its negative lobes ring at edges, so each output pixel is
// clamped per channel to the min/max of the 2x2 source pixels around it (no
// overshoot, no negative radiance). Depth and distance take the nearest
// source sample: a blend of two surfaces' depths is a depth nothing has.
//
// HDR radiance is filtered through a reversible tonemap (Karis 2014, as
// temporal upsamplers do): each source pixel is scaled by 1 / (1 + k L),
// L its luminance and k the exposure, filtered and clamped, then scaled
// back by 1 / (1 - k L'). Without it, the few pixels around the sun's disk
// (10^5 times the sky) take a share of its radiance through the filter's
// weights and dominate the frame's error; with it, a pixel bright enough to
// saturate the display counts as much as one that just does.
//
// Work is split into bands of output rows on the job system; each output
// pixel is computed from the source alone, in a fixed order, so results are
// bit-identical for any thread count.
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/job_system.h"

namespace cr {

class Upscaler {
 public:
  Upscaler(int source_width, int source_height, int width, int height);

  // `source` holds source_width x source_height pixels, `out` receives
  // width x height (both row-major); `out` is resized. `exposure` is k of
  // the reversible tonemap (tonemap.h's exposure_scale); 0 filters the
  // radiance as it is.
  void color(const std::vector<glm::vec3>& source, std::vector<glm::vec3>& out, JobSystem& jobs,
             float exposure = 0.0f) const;
  void nearest(const std::vector<float>& source, std::vector<float>& out, JobSystem& jobs) const;

 private:
  // Where one output column (or row) samples the source along its axis.
  struct Taps {
    int index[4];     // source pixels under the kernel, clamped to the image; [1], [2] bracket the centre
    float weight[4];  // Catmull-Rom weights of those pixels
    int nearest;      // the source pixel containing the output pixel's centre
  };
  static std::vector<Taps> axis_taps(int source, int output);

  int source_width_, width_, height_;
  std::vector<Taps> columns_, rows_;
};

}  // namespace cr

#pragma once
// The LUTs of a spectral sampling's groups combined into one RGB LUT: per
// texel, each wavelength's value times its sRGB weights (spectral_sampling.h),
// summed in a fixed order (the same bits for any thread count). The
// combination is linear, so radiance and transmittance mix alike; results
// outside [lo, hi] (out of the sRGB gamut, or a transmittance over 1 through
// the matrix's negative lobes) are clipped.
#include <cstddef>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "atmosphere/spectral_sampling.h"
#include "engine/core/job_system.h"

namespace cr {

inline void mix_texels(glm::vec3* out, size_t n, const std::vector<const glm::vec3*>& groups, const SpectralSampling& s,
                       JobSystem& jobs, float lo = -std::numeric_limits<float>::infinity(),
                       float hi = std::numeric_limits<float>::infinity()) {
  std::vector<glm::vec3> w(s.weights.size());
  for (size_t i = 0; i < w.size(); ++i) w[i] = glm::vec3(s.weights[i]);
  jobs.parallel_for("atmosphere.spectral_mix", n, 2048, [&](size_t begin, size_t end) {
    for (size_t t = begin; t < end; ++t) {
      glm::vec3 sum(0.0f);
      for (size_t i = 0; i < w.size(); ++i) sum += w[i] * groups[i / 3][t][int(i % 3)];
      out[t] = glm::clamp(sum, glm::vec3(lo), glm::vec3(hi));
    }
  });
}

// mix_texels over the same image of every group LUT: `image(lut)` returns it.
template <class Lut, class ImageOf>
void mix_image(glm::vec3* out, size_t n, const std::vector<const Lut*>& groups, const SpectralSampling& s,
               JobSystem& jobs, ImageOf image, float lo = -std::numeric_limits<float>::infinity(),
               float hi = std::numeric_limits<float>::infinity()) {
  std::vector<const glm::vec3*> in;
  for (const Lut* g : groups) in.push_back(image(*g).texels.data());
  mix_texels(out, n, in, s, jobs, lo, hi);
}

}  // namespace cr
